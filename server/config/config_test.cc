#include "server/config/config.h"
#include "server/config/config_file.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <array>
#include <cstdlib>
#include <fstream>
#include <numbers>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

using testing::SourceDir;

class ConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor_config_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Loads `yaml` and returns the error message, or "" when it loaded.
  std::string ErrorOf(const std::string& yaml, const ConfigOverrides& overrides = {}) {
    std::ofstream(dir_ / "c.yaml") << yaml;
    try {
      LoadConfig(dir_ / "c.yaml", overrides);
      return "";
    } catch (const ConfigError& e) {
      return e.what();
    }
  }

  fs::path dir_;
};

TEST_F(ConfigTest, EveryShippedConfigLoadsAndItsWorldExists) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(SourceDir() / "config")) {
    if (entry.path().extension() != ".yaml") continue;
    ++count;
    SCOPED_TRACE(entry.path().string());
    const Config c = LoadConfig(entry.path());
    EXPECT_TRUE(fs::exists(c.sim.world)) << c.sim.world;
  }
  EXPECT_GE(count, 2);
}

TEST_F(ConfigTest, DefaultsApplyToAnEmptyFileButTheWorldIsRequired) {
  EXPECT_EQ(ErrorOf("sim: {world: w.yaml}\n"), "");
  EXPECT_NE(ErrorOf("log: {level: info}\n").find("sim.world: required"), std::string::npos);
}

TEST_F(ConfigTest, RelativePathsAreRelativeToTheFile) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w/map.yaml}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").sim.world, dir_ / "w/map.yaml");
}

TEST_F(ConfigTest, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_NE(ErrorOf("sim: {world: w.yaml, camera: {widht: 640}}\n").find("sim.camera.widht: unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nserverr: {}\n").find("serverr: unknown key"), std::string::npos);
}

// Found by fuzz_config: YAML allows a mapping as a key ("? {a: 1}: 2"), which used to throw yaml-cpp's own
// exception out of LoadConfig instead of a ConfigError.
TEST_F(ConfigTest, KeysThatAreNotNamesAreNamedWithTheirSection) {
  const std::string e = ErrorOf("sim:\n  world: w.yaml\n  base:\n    ? max_angular_rps: 1.5\n    : 2\n");
  EXPECT_NE(e.find("sim.base: a key must be a plain name, got a mapping (line 4)"), std::string::npos) << e;
  const std::string top = ErrorOf("sim: {world: w.yaml}\n? [a, b]\n: 1\n");
  EXPECT_NE(top.find("the file: a key must be a plain name, got a list (line 2)"), std::string::npos) << top;
}

TEST_F(ConfigTest, WrongTypesAreNamed) {
  const std::string e = ErrorOf("sim: {world: w.yaml}\nserver: {port: eighty}\n");
  EXPECT_NE(e.find("server.port: expected an integer, got 'eighty'"), std::string::npos) << e;
  EXPECT_NE(ErrorOf("sim: {world: w.yaml, base: [1, 2]}\n").find("sim.base: expected a mapping"), std::string::npos);
  EXPECT_NE(ErrorOf("sim: {enabled: maybe}\n").find("sim.enabled: moved to devices.base.driver"), std::string::npos);
}

TEST_F(ConfigTest, OutOfRangeValuesAreNamedWithTheRange) {
  const std::string e = ErrorOf("sim: {world: w.yaml, camera: {width: 5}}\n");
  EXPECT_NE(e.find("sim.camera.width: must be between 16 and 4096, got 5"), std::string::npos) << e;
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nsafety: {teleop_deadman_s: -1}\n").find("safety.teleop_deadman_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml, camera: {min_range_m: 7, max_range_m: 6}}\n").find("min_range_m"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nlog: {level: loud}\n").find("log.level"), std::string::npos);
}

TEST_F(ConfigTest, PolarGainsAreCheckedForConvergence) {
  const std::string e = ErrorOf("sim: {world: w.yaml}\nmission: {k_beta: 0.5}\n");
  EXPECT_NE(e.find("k_beta must be < 0"), std::string::npos) << e;
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nmission: {k_rho: 3, k_alpha: 2}\n").find("k_alpha - k_rho must be > 0"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("sim: {world: w.yaml}\nmission: {k_rho: 0.5, k_alpha: 1.5, k_beta: -0.3}\n"), "");
}

TEST_F(ConfigTest, MorpIlDrivesWithTheNetworkItNamesAndOnlyOneThatFits) {
  // Read only when it drives: the default policy does not need the file.
  EXPECT_EQ(ErrorOf("sim: {world: w.yaml}\nmission: {morp_il: {weights: none.weights}}\n"), "");
  std::string e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: morp-il, morp_il: {weights: none.weights}}\n");
  EXPECT_NE(e.find("mission.morp_il.weights: "), std::string::npos) << e;
  EXPECT_NE(e.find("none.weights: cannot open the weights"), std::string::npos) << e;
  // A network of the wrong shape for the history.
  using nav::Activation;
  nav::Mlp::Random(std::array{36, 8, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 1)
      .Save(dir_ / "h3.weights");
  e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: morp-il, morp_il: {weights: h3.weights}}\n");
  EXPECT_NE(e.find("a network of 36 inputs and 2 outputs; want 48 (history 4) and 2"), std::string::npos) << e;
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nmission: {policy: morp-il, morp_il: {weights: h3.weights, "
                                    "history: 3}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(c.mission.policy, nav::LocalPolicyKind::kMorpIl);
  ASSERT_NE(c.mission.navigator.learned, nullptr);
  EXPECT_EQ(c.mission.navigator.learned->inputs(), 36);
  EXPECT_EQ(c.mission.navigator.il.max_linear_mps, 0.26);  // the network's own scale, not the mission's top speed
  // The shipped network drives (config/policies/morp_il.weights, as the shipped configuration names it).
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nmission: {policy: morp-il, morp_il: {weights: "
                                 << (SourceDir() / "config/policies/morp_il.weights").string() << "}}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").mission.navigator.learned->inputs(), 48);
  e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: sarl}\n");
  EXPECT_NE(e.find("mission.policy: must be morp-rb, voxel-reactive, morp-il, takiguchi or flmc, got 'sarl'"),
            std::string::npos)
      << e;
}

// The ground test: MORP unless afds is chosen; AFDS takes the lanes' step and drop heights and its own grid.
TEST_F(ConfigTest, TheGroundTestIsMorpOrAfdsWithItsGrid) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").ground.test, GroundTest::kMorp);
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nground: {test: afds, max_step_m: 0.05, "
                                    "afds: {grid_columns: 12, grid_rows: 9}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(c.ground.test, GroundTest::kAfds);
  EXPECT_EQ(c.ground.afds.grid_columns, 12);
  EXPECT_EQ(c.ground.afds.grid_rows, 9);
  EXPECT_DOUBLE_EQ(c.ground.afds.max_step_m, 0.05);
  std::string e = ErrorOf("sim: {world: w.yaml}\nground: {test: ransac}\n");
  EXPECT_NE(e.find("ground.test: must be morp or afds, got 'ransac'"), std::string::npos) << e;
  e = ErrorOf("sim: {world: w.yaml}\nground: {afds: {grid_columns: 40}}\n");
  EXPECT_NE(e.find("ground.afds.grid_columns"), std::string::npos) << e;
}

// ASNS's camera: the simulated stereo camera's third view, the pairs' bands, and the multi-view filter.
TEST_F(ConfigTest, TheStereoCamerasWidePairAndMultiViewFilterAreReadAndChecked) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml, camera: {stereo: {enabled: true, wide_baseline_m: 0.24, "
                                    "near_max_m: 1.8, far_min_m: 1.5}}}\n"
                                    "multi_view: {enabled: true, views: 3, window: 4, cell_m: 0.08}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_DOUBLE_EQ(c.sim.robot.stereo.wide_baseline_m, 0.24);
  EXPECT_EQ(c.sim.robot.stereo.wide_disparities, 64);
  EXPECT_DOUBLE_EQ(c.sim.robot.stereo.fusion.near_max_m, 1.8);
  EXPECT_DOUBLE_EQ(c.sim.robot.stereo.fusion.far_min_m, 1.5);
  EXPECT_TRUE(c.multi_view.enabled);
  EXPECT_EQ(c.multi_view.views, 3);
  EXPECT_EQ(c.multi_view.window, 4);
  EXPECT_DOUBLE_EQ(c.multi_view.cell_m, 0.08);
  std::string e = ErrorOf("sim: {world: w.yaml, camera: {stereo: {wide_baseline_m: 0.1}}}\n");
  EXPECT_NE(e.find("sim.camera.stereo.wide_baseline_m: 0 (none) or longer than baseline_m"), std::string::npos) << e;
  e = ErrorOf("sim: {world: w.yaml, camera: {stereo: {near_max_m: 1.0, far_min_m: 1.5}}}\n");
  EXPECT_NE(e.find("sim.camera.stereo.far_min_m: at most near_max_m"), std::string::npos) << e;
  e = ErrorOf("sim: {world: w.yaml}\nmulti_view: {views: 4}\n");
  EXPECT_NE(e.find("multi_view.views"), std::string::npos) << e;
}

// ASNS's fuzzy controllers: corridor's rules unless files are named; a rule base that cannot run stops start-up.
TEST_F(ConfigTest, TheFuzzyPolicyReadsItsRuleBasesAndRefusesOnesThatCannotRun) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nmission: {policy: flmc, flmc: {rotate_above_deg: 45}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(c.mission.policy, nav::LocalPolicyKind::kFlmc);
  EXPECT_NEAR(c.mission.navigator.flmc.rotate_above_rad, M_PI / 4, 1e-12);
  EXPECT_TRUE(c.mission.navigator.flmc.motion_fll.empty());
  EXPECT_DOUBLE_EQ(c.mission.navigator.flmc.max_linear_mps, c.mission.navigator.follower.max_linear_mps);
  // A rule base of the user's own, relative to the configuration: corridor's, with the rotation slowed.
  std::string rotation = nav::DefaultFlmcRules("rotation");
  rotation.replace(rotation.find("bearing is PB then angular is PB"), 32, "bearing is PB then angular is PM");
  std::ofstream(dir_ / "rotation.fll") << rotation;
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nmission: {policy: flmc, flmc: {rotation_rules: "
                                    "rotation.fll}}\n";
  EXPECT_NE(LoadConfig(dir_ / "c.yaml").mission.navigator.flmc.rotation_fll.find("angular is PM"), std::string::npos);
  std::string e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: flmc, flmc: {motion_rules: none.fll}}\n");
  EXPECT_NE(e.find("mission.flmc.motion_rules: " + (dir_ / "none.fll").string() + ": cannot be read"),
            std::string::npos)
      << e;
  std::ofstream(dir_ / "avoid.fll") << nav::DefaultFlmcRules("rotation");
  e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: flmc, flmc: {avoidance_rules: avoid.fll}}\n");
  EXPECT_NE(e.find("mission.flmc: flmc avoidance: no input variable 'left'"), std::string::npos) << e;
}

TEST_F(ConfigTest, TakiguchisPolicyNeedsANetworkOfItsShape) {
  std::string e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: takiguchi}\n");
  EXPECT_NE(e.find("mission.takiguchi.weights: required with policy takiguchi"), std::string::npos) << e;
  using nav::Activation;
  nav::Mlp::Random(std::array{274, 16, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 1)
      .Save(dir_ / "two.weights");
  e = ErrorOf("sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: two.weights}}\n");
  EXPECT_NE(e.find("mission.takiguchi.weights: takiguchi: the network has 274 inputs and 2 outputs"), std::string::npos)
      << e;
  nav::Mlp::Random(std::array{274, 16, 20}, std::array{Activation::kRelu, Activation::kSoftmax}, 1)
      .Save(dir_ / "twenty.weights");
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: "
                                    "twenty.weights, speed_mps: 0.3}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(c.mission.policy, nav::LocalPolicyKind::kTakiguchi);
  ASSERT_NE(c.mission.navigator.direction, nullptr);
  EXPECT_EQ(c.mission.navigator.takiguchi.max_linear_mps, 0.3);
  // Rays all round take a network with as many inputs; the message names the rays and the field.
  e = ErrorOf(
      "sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: twenty.weights, rays: 180, "
      "field_deg: 360}}\n");
  EXPECT_NE(e.find("the policy 541 and 20 (rays 180 over 360 degrees"), std::string::npos) << e;
  nav::Mlp::Random(std::array{541, 16, 20}, std::array{Activation::kRelu, Activation::kSoftmax}, 1)
      .Save(dir_ / "round.weights");
  std::ofstream(dir_ / "r.yaml") << "sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: "
                                    "round.weights, rays: 180, field_deg: 360}}\n";
  EXPECT_NEAR(LoadConfig(dir_ / "r.yaml").mission.navigator.takiguchi.field_rad, 2.0 * std::numbers::pi, 1e-12);
  // The shipped networks drive: the camera's with the paper's rays, the laser's with 180 all round.
  const std::string shipped = (SourceDir() / "config/policies").string();
  std::ofstream(dir_ / "s.yaml") << "sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: "
                                 << shipped << "/takiguchi.weights}}\n";
  EXPECT_EQ(LoadConfig(dir_ / "s.yaml").mission.navigator.direction->inputs(), 274);
  std::ofstream(dir_ / "s.yaml") << "sim: {world: w.yaml}\nmission: {policy: takiguchi, takiguchi: {weights: "
                                 << shipped << "/takiguchi_laser.weights, rays: 180, field_deg: 360}}\n";
  EXPECT_EQ(LoadConfig(dir_ / "s.yaml").mission.navigator.direction->inputs(), 541);
  e = ErrorOf("sim: {world: w.yaml}\nmission: {takiguchi: {field_deg: 400}}\n");
  EXPECT_NE(e.find("mission.takiguchi.field_deg"), std::string::npos) << e;
}

TEST_F(ConfigTest, TheVdaBrokerIsOffByDefaultAndTheFlagSetsIt) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").fleet.vda5050.broker, "");
  ConfigOverrides flag;
  flag.mqtt = "mqtt://127.0.0.1:1883";
  const Config c = LoadConfig(dir_ / "c.yaml", flag);
  EXPECT_EQ(c.fleet.vda5050.broker, "mqtt://127.0.0.1:1883");
  EXPECT_EQ(c.fleet.vda5050.interface_name, "uagv");
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nfleet: {vda5050: {broker: 'http://x:80'}}\n").find("fleet.vda5050.broker"),
            std::string::npos);
  flag.mqtt = "127.0.0.1";
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\n", flag).find("fleet.vda5050.broker"), std::string::npos);
  EXPECT_NE(
      ErrorOf("sim: {world: w.yaml}\nfleet: {vda5050: {serial_number: 'a/#'}}\n").find("fleet.vda5050.serial_number"),
      std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nfleet: {vda5050: {qos: 3}}\n").find("fleet.vda5050.qos"), std::string::npos);
}

TEST_F(ConfigTest, DdsIsOffByDefaultAndItsDomainComesFromTheEnvironmentUnlessSet) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n";
  const Config off = LoadConfig(dir_ / "c.yaml");
  EXPECT_FALSE(off.dds.enabled);
  EXPECT_FALSE(off.dds.allow_writes);
  ::unsetenv("ROS_DOMAIN_ID");
  EXPECT_EQ(DdsDomain(off.dds), 0);
  ::setenv("ROS_DOMAIN_ID", "42", 1);
  EXPECT_EQ(DdsDomain(off.dds), 42);
  ::setenv("ROS_DOMAIN_ID", "300", 1);
  EXPECT_THROW(DdsDomain(off.dds), ConfigError);
  ::setenv("ROS_DOMAIN_ID", "x", 1);
  EXPECT_THROW(DdsDomain(off.dds), ConfigError);
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n"
                                    "dds: {enabled: true, domain_id: 7, peers: [127.0.0.1], interfaces: [lo]}\n";
  const Config on = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(DdsDomain(on.dds), 7);  // the configuration's, not the environment's
  ::unsetenv("ROS_DOMAIN_ID");
  EXPECT_EQ(on.dds.peers, std::vector<std::string>{"127.0.0.1"});
  EXPECT_EQ(on.dds.interfaces, std::vector<std::string>{"lo"});
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndds: {domain_id: 233}\n").find("dds.domain_id"), std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndds: {peers: [robot.local]}\n").find("dds.peers"), std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndds: {peers: 127.0.0.1}\n").find("dds.peers"), std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndds: {camera_hz: -1}\n").find("dds.camera_hz"), std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndds: {devices: {base: {odom_topic: /odom}}}\n").find("dds.devices: moved"),
            std::string::npos);
}

// devices.*: each slot's driver with its own options; the simulator's robot is all or nothing; DDS drivers need DDS.
// A stereo camera: its calibration file is read with the configuration, and one that cannot serve stops start-up
// with the key and the reason.
TEST_F(ConfigTest, AStereoCameraReadsItsCalibrationAndChecksIt) {
  drivers::stereo::StereoCalibration pair;
  pair.image_size = {640, 480};
  pair.left.matrix = pair.right.matrix = {500, 0, 320, 0, 500, 240, 0, 0, 1};
  pair.translation_m = {-0.12, 0, 0};
  drivers::stereo::SaveStereoCalibration(dir_ / "pair.yaml", pair);
  const std::string robot =
      "map: {file: x.yaml}\ndevices:\n  base: {driver: kobuki, port: /dev/kobuki}\n"
      "  laser: {driver: none}\n";
  std::ofstream(dir_ / "c.yaml") << robot
                                 << "  camera: {driver: stereo, calibration: pair.yaml, format: yuyv, fps: 15, "
                                    "depth_width: 320, matcher: bm, block_px: 15, tilt_deg: 5}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  const drivers::stereo::StereoCameraOptions& stereo = c.devices.camera.stereo;
  EXPECT_EQ(c.devices.camera.driver, DeviceDriver::kStereo);
  EXPECT_EQ(stereo.layout, drivers::stereo::StereoLayout::kSideBySide);
  EXPECT_EQ(stereo.format, drivers::stereo::VideoFormat::kYuyv);
  EXPECT_DOUBLE_EQ(stereo.calibration.baseline_m(), 0.12);  // relative to the configuration's directory
  EXPECT_EQ(stereo.depth.matcher.kind, drivers::stereo::MatcherKind::kBlock);
  EXPECT_EQ(stereo.depth.matcher.block_px, 15);
  EXPECT_DOUBLE_EQ(stereo.tilt_deg, 5.0);
  const auto error = [&](const std::string& camera) { return ErrorOf(robot + "  camera: " + camera + "\n"); };
  EXPECT_NE(error("{driver: stereo}").find("devices.camera.calibration: required (a file from corridor-stereo"),
            std::string::npos);
  // ASNS's wide baseline: a third camera with the left camera's calibration with it, both or neither.
  drivers::stereo::StereoCalibration wide = pair;
  wide.translation_m = {-0.24, 0.0, 0.0};
  drivers::stereo::SaveStereoCalibration(dir_ / "wide.yaml", wide);
  std::ofstream(dir_ / "c.yaml") << robot
                                 << "  camera: {driver: stereo, calibration: pair.yaml, third_node: /dev/video4, "
                                    "wide_calibration: wide.yaml, far_min_m: 1.5}\n";
  const Config three = LoadConfig(dir_ / "c.yaml");
  ASSERT_TRUE(three.devices.camera.stereo.wide_calibration);
  EXPECT_DOUBLE_EQ(three.devices.camera.stereo.wide_calibration->baseline_m(), 0.24);
  EXPECT_EQ(three.devices.camera.stereo.third_node, "/dev/video4");
  EXPECT_DOUBLE_EQ(three.devices.camera.stereo.fusion.far_min_m, 1.5);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, third_node: /dev/video4}")
                .find("devices.camera.third_node, wide_calibration: both or neither"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, third_node: /dev/video4, wide_calibration: pair.yaml}")
                .find("devices.camera.wide_calibration: its baseline must be longer"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: none.yaml}")
                .find("devices.camera.calibration: " + (dir_ / "none.yaml").string() + ": no such file"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, width: 1280, height: 720}")
                .find("devices.camera.calibration: made for 640 x 480 px views, the camera's are 1280 x 720"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, disparities: 60}")
                .find("disparities: a multiple of 16 from 16 to 512, got 60"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, layout: two-cameras, left_node: /dev/video0}")
                .find("devices.camera.left_node, right_node: required with two cameras"),
            std::string::npos);
  EXPECT_NE(error("{driver: stereo, calibration: pair.yaml, fps: 2}").find("devices.camera.fps: frames every"),
            std::string::npos);
}

TEST_F(ConfigTest, DeviceSlotsTakeTheirDriversOptionsAndMixOnlyAsTheyCan) {
  const std::string dds = "dds: {enabled: true, peers: [127.0.0.1], interfaces: [lo]}\nmap: {file: x.yaml}\n";
  std::ofstream(dir_ / "c.yaml")
      << dds
      << "devices:\n"
         "  base: {driver: create2, port: /dev/ttyUSB0, wheel_diameter_m: 0.07, stale_s: 0.04}\n"
         "  laser: {driver: rplidar, port: /dev/corridor/rplidar, baud_rate: 256000, mount_yaw_deg: 180, scan: "
         "express}\n"
         "  camera: {driver: dds, depth_topic: /cam/depth, info_wait_s: 3}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_FALSE(Simulated(c));
  EXPECT_EQ(c.devices.base.driver, DeviceDriver::kCreate2);
  EXPECT_EQ(c.devices.base.create2.port, "/dev/ttyUSB0");
  EXPECT_DOUBLE_EQ(c.devices.base.create2.wheels.wheel_diameter_m, 0.07);
  EXPECT_DOUBLE_EQ(c.devices.base.create2.stale_s, 0.04);
  EXPECT_EQ(c.devices.laser.rplidar.baud_rate, 256000);
  EXPECT_EQ(c.devices.laser.rplidar.scan_mode, drivers::rplidar::ScanMode::kExpress);
  EXPECT_NEAR(c.devices.laser.rplidar.base_T_laser.yaw_rad, M_PI, 1e-9);
  EXPECT_EQ(c.devices.camera.dds.depth_topic, "/cam/depth");
  EXPECT_DOUBLE_EQ(c.devices.camera.info_wait_s, 3.0);
  EXPECT_TRUE(c.safety.require_laser);
  EXPECT_FALSE(c.sim.robot.laser.enabled);

  // Defaults: the simulator's robot with its laser.
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n";
  const Config sim = LoadConfig(dir_ / "c.yaml");
  EXPECT_TRUE(Simulated(sim));
  EXPECT_TRUE(sim.sim.robot.laser.enabled);
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\ndevices: {laser: {driver: none}}\n";
  const Config blind = LoadConfig(dir_ / "c.yaml");
  EXPECT_FALSE(blind.sim.robot.laser.enabled);
  EXPECT_FALSE(blind.safety.require_laser);

  const auto error = [&](const std::string& devices) { return ErrorOf(dds + "devices: " + devices + "\n"); };
  EXPECT_NE(
      error("{base: {driver: kobold}}")
          .find("devices.base.driver: must be sim, dds, create2, kobuki, turtlebot3 or serial-text, got 'kobold'"),
      std::string::npos);
  EXPECT_NE(error("{base: {driver: create2}, camera: {driver: dds}}").find("devices.base.port: required"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: create2, port: /dev/x, baud_rate: 12345}, camera: {driver: dds}}")
                .find("devices.base.baud_rate"),
            std::string::npos);
  // A Kobuki with the create2's keys, its battery's voltages its own; a Create 2 knows no battery voltages.
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: kobuki, port: /dev/kobuki, max_linear_mps: 0.7, "
                                    "battery_empty_v: 13.0}\n  laser: {driver: none}\n  camera: {driver: dds}\n";
  const Config kobuki = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(kobuki.devices.base.driver, DeviceDriver::kKobuki);
  EXPECT_EQ(kobuki.devices.base.kobuki.port, "/dev/kobuki");
  EXPECT_DOUBLE_EQ(kobuki.devices.base.kobuki.max_linear_mps, 0.7);
  EXPECT_DOUBLE_EQ(kobuki.devices.base.kobuki.battery_empty_v, 13.0);
  EXPECT_DOUBLE_EQ(kobuki.devices.base.kobuki.wheels.track_m, 0.230);
  EXPECT_NE(error("{base: {driver: create2, port: /dev/x, max_linear_mps: 0.7}, camera: {driver: dds}}")
                .find("devices.base.max_linear_mps"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: create2, port: /dev/x, battery_full_v: 16}, camera: {driver: dds}}")
                .find("devices.base.battery_full_v: unknown"),
            std::string::npos);
  // A TurtleBot 3: a Burger unless told otherwise (a Waffle Pi's track).
  std::ofstream(dir_ / "c.yaml")
      << dds
      << "devices:\n  base: {driver: turtlebot3, port: /dev/corridor/opencr, track_m: 0.287}\n"
         "  laser: {driver: none}\n  camera: {driver: dds}\n";
  const Config turtlebot3 = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(turtlebot3.devices.base.driver, DeviceDriver::kTurtlebot3);
  EXPECT_EQ(turtlebot3.devices.base.turtlebot3.baud_rate, 1000000);
  EXPECT_DOUBLE_EQ(turtlebot3.devices.base.turtlebot3.wheels.track_m, 0.287);
  EXPECT_DOUBLE_EQ(turtlebot3.devices.base.turtlebot3.wheels.counts_per_revolution, 4096.0);
  EXPECT_NE(error("{base: {driver: turtlebot3, port: /dev/x, max_linear_mps: 0.5}, camera: {driver: dds}}")
                .find("devices.base.max_linear_mps"),
            std::string::npos);
  // A home-made base on the serial text protocol: its wheels are its own, and required.
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: serial-text, port: /dev/corridor/arduino, "
                                    "wheel_diameter_m: 0.065, track_m: 0.2, counts_per_revolution: 1920, "
                                    "pid_rate_hz: 1}\n  laser: {driver: none}\n  camera: {driver: dds}\n";
  const Config home_made = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(home_made.devices.base.driver, DeviceDriver::kSerialText);
  EXPECT_EQ(home_made.devices.base.serial_text.baud_rate, 57600);
  EXPECT_DOUBLE_EQ(home_made.devices.base.serial_text.wheels.counts_per_revolution, 1920.0);
  EXPECT_DOUBLE_EQ(home_made.devices.base.serial_text.pid_rate_hz, 1.0);
  EXPECT_NE(error("{base: {driver: serial-text, port: /dev/x, track_m: 0.2}, camera: {driver: dds}}")
                .find("devices.base.wheel_diameter_m: required with this driver (the base's own wheels"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x, pid_rate_hz: 30}, camera: {driver: dds}}")
                .find("devices.base.pid_rate_hz: unknown"),
            std::string::npos);
  // A Hokuyo on Ethernet or USB; a RealSense and an OpenNI2 camera with their intrinsics and mounting.
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: kobuki, port: /dev/kobuki}\n"
                                    "  laser: {driver: hokuyo, port: 192.168.0.10:10940, mount_yaw_deg: 90}\n"
                                    "  camera: {driver: realsense, fx: 386.2, fy: 386.1, fps: 15, tilt_deg: 5}\n";
  const Config ust = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(ust.devices.laser.driver, DeviceDriver::kHokuyo);
  EXPECT_EQ(ust.devices.laser.hokuyo.port, "192.168.0.10:10940");
  EXPECT_NEAR(ust.devices.laser.hokuyo.base_T_laser.yaw_rad, M_PI / 2, 1e-9);
  EXPECT_EQ(ust.devices.camera.driver, DeviceDriver::kRealsense);
  EXPECT_DOUBLE_EQ(ust.devices.camera.realsense.camera.fx, 386.2);
  EXPECT_EQ(ust.devices.camera.realsense.camera.fps, 15);
  EXPECT_DOUBLE_EQ(ust.devices.camera.realsense.depth_scale_m, 0.001);
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: kobuki, port: /dev/kobuki}\n"
                                    "  laser: {driver: hokuyo, port: ttyACM0}\n"
                                    "  camera: {driver: openni2, uri: '1d27/0601@1/5', color: false}\n";
  const Config urg = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(urg.devices.laser.hokuyo.port, (dir_ / "ttyACM0").string());  // relative to the configuration
  EXPECT_EQ(urg.devices.camera.openni2.uri, "1d27/0601@1/5");
  EXPECT_FALSE(urg.devices.camera.openni2.color);
  // A TurtleBot 3's laser: an LDS-02 unless said, an LDS-01 measuring to 3.5 m.
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: turtlebot3, port: /dev/corridor/opencr}\n"
                                    "  laser: {driver: lds, port: /dev/corridor/lds}\n  camera: {driver: none}\n";
  const Config burger = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(burger.devices.laser.driver, DeviceDriver::kLds);
  EXPECT_EQ(burger.devices.laser.lds.model, drivers::lds::Model::kLds02);
  EXPECT_EQ(burger.devices.laser.lds.baud_rate, 230400);
  EXPECT_DOUBLE_EQ(burger.devices.laser.lds.sweep.range_max_m, 8.0);
  std::ofstream(dir_ / "c.yaml") << dds
                                 << "devices:\n  base: {driver: turtlebot3, port: /dev/corridor/opencr}\n"
                                    "  laser: {driver: lds, model: lds-01, port: /dev/corridor/lds}\n"
                                    "  camera: {driver: none}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").devices.laser.lds.model, drivers::lds::Model::kLds01);
  EXPECT_DOUBLE_EQ(LoadConfig(dir_ / "c.yaml").devices.laser.lds.sweep.range_max_m, 3.5);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x}, laser: {driver: lds, model: lds-03, port: /dev/x}, camera: "
                  "{driver: none}}")
                .find("devices.laser.model"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x}, laser: {driver: hokuyo, port: 'robot:http'}, camera: "
                  "{driver: none}}")
                .find("devices.laser.port: 'robot:http': http is not a TCP port"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x}, laser: {driver: hokuyo}, camera: {driver: none}}")
                .find("devices.laser.port: required"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x}, laser: {driver: none}, camera: {driver: realsense, fx: 380}}")
                .find("devices.camera.fx, fy: both or neither"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: kobuki, port: /dev/x}, laser: {driver: none}, camera: {driver: openni2, fps: 5}}")
                .find("devices.camera.fps: frames every"),
            std::string::npos);
  // A key of another driver is unknown to this one.
  EXPECT_NE(error("{base: {driver: dds, port: /dev/x}, camera: {driver: dds}}").find("devices.base.port: unknown"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: dds}, camera: {driver: sim}}").find("devices.camera.driver: sim with a dds base"),
            std::string::npos);
  EXPECT_NE(error("{laser: {driver: rplidar, port: /dev/x}}").find("devices.laser.driver: rplidar with a sim base"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: dds, odom_topic: 'odom odom'}, camera: {driver: dds}}")
                .find("devices.base.odom_topic: 'odom odom' is not a ROS 2 topic name"),
            std::string::npos);
  EXPECT_NE(ErrorOf("map: {file: x.yaml}\n"
                    "devices: {base: {driver: dds}, laser: {driver: none}, camera: {driver: dds}}\n")
                .find("needs dds.enabled"),
            std::string::npos);
  // With the base over DDS, ROS tools' velocities must not arrive on the base's own command topic.
  EXPECT_NE(ErrorOf("map: {file: x.yaml}\ndds: {enabled: true, allow_writes: true}\n"
                    "devices: {base: {driver: dds}, laser: {driver: none}, camera: {driver: dds}}\n")
                .find("dds.cmd_vel_topic"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf("dds: {enabled: true}\ndevices: {base: {driver: dds}, laser: {driver: none}, camera: {driver: dds}}\n")
          .find("map.file: required"),
      std::string::npos);
  // The old places of the keys say where they went.
  EXPECT_NE(ErrorOf("sim: {world: w.yaml, laser: {enabled: false}}\n").find("sim.laser.enabled: moved to devices"),
            std::string::npos);
  // A simulated camera slower than the gate's patience would never drive forward; without a camera it does not count.
  EXPECT_NE(ErrorOf("sim: {world: w.yaml, camera: {rate_hz: 10}}\n").find("sim.camera.rate_hz"), std::string::npos);
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml, camera: {rate_hz: 10}}\ndevices: {camera: {driver: none}}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").devices.camera.driver, DeviceDriver::kNone);
  // A robot with neither a camera nor a laser sees nothing.
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndevices: {camera: {driver: none}, laser: {driver: none}}\n")
                .find("devices.camera.driver: none with no laser either"),
            std::string::npos);
  EXPECT_NE(error("{base: {driver: create2, port: /dev/x}, laser: {driver: rplidar, port: /dev/y}, camera: "
                  "{driver: none, depth_topic: /d}}")
                .find("devices.camera.depth_topic: unknown"),
            std::string::npos);
}

TEST_F(ConfigTest, ADdsSecurityEnclaveIsFoundBesideTheConfigurationAndMustBeWhole) {
  fs::create_directories(dir_ / "enclave");
  for (const char* file : drivers::dds::kEnclaveFiles) std::ofstream(dir_ / "enclave" / file) << "x";
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\ndds: {security: {enclave: enclave}}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml").dds.security_enclave, dir_ / "enclave");
  fs::remove(dir_ / "enclave" / "permissions.p7s");
  const std::string error = ErrorOf("sim: {world: w.yaml}\ndds: {security: {enclave: enclave}}\n");
  EXPECT_NE(error.find("dds.security.enclave"), std::string::npos) << error;
  EXPECT_NE(error.find("permissions.p7s is missing"), std::string::npos) << error;
}

TEST_F(ConfigTest, DoorsTheirControllerAndTheSimulatorsDoorsAreReadAndChecked) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml, doors: [{id: d1, x1_m: 4, y1_m: 1, x2_m: 4, y2_m: 2}]}\n"
                                    "doors:\n"
                                    "  hold_m: 1.2\n"
                                    "  controller:\n"
                                    "    open: {url: 'http://127.0.0.1:9000/doors/{door}/open'}\n"
                                    "    headers: [{name: Authorization, value: Bearer x}]\n"
                                    "  list: [{id: d2, map: willow, x1_m: 1, y1_m: 2, x2_m: 3, y2_m: 2}]\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  ASSERT_EQ(c.sim.robot.doors.size(), 1u);
  EXPECT_EQ(c.sim.robot.doors[0].to.y(), 2.0);
  EXPECT_DOUBLE_EQ(c.mission.doors.hold_m, 1.2);
  EXPECT_EQ(c.doors.controller.open.method, "POST");
  EXPECT_EQ(c.doors.controller.headers.size(), 1u);
  ASSERT_EQ(c.doors.list.size(), 1u);
  EXPECT_EQ(c.doors.list[0].map, "willow");
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndoors: {controller: {open: {url: 'ftp://x'}}}\n")
                .find("doors.controller.open.url"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndoors: {controller: {open: {method: FETCH}}}\n").find("method"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndoors: {request_m: 1, hold_m: 2}\n").find("doors.request_m"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ndoors: {list: [{x1_m: 1}]}\n").find("doors.list[0].id"), std::string::npos);
}

TEST_F(ConfigTest, ABuildingsFloorsLiftsAndLiftControllerAreReadAndChecked) {
  std::ofstream(dir_ / "c.yaml") << "building:\n"
                                    "  floors: [{name: L1, map: a/one.yaml}, {name: L2, map: two.yaml}]\n"
                                    "  lifts:\n"
                                    "    - id: east\n"
                                    "      stops:\n"
                                    "        - {floor: L1, x1_m: 2, y1_m: 0, x2_m: 2, y2_m: 1,"
                                    " lobby_x_m: 1, lobby_y_m: 0.5}\n"
                                    "        - {floor: L2, x1_m: 5, y1_m: 3, x2_m: 6, y2_m: 3, lobby_x_m: 5.5,"
                                    " lobby_y_m: 2, lobby_yaw_deg: 90}\n"
                                    "  ride: {call_timeout_s: 30}\n"
                                    "  controller: {call: {url: 'http://127.0.0.1:9000/lifts/{lift}'}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");  // no sim.world: the floors are the simulator's world
  ASSERT_EQ(c.building.floors.size(), 2u);
  EXPECT_EQ(c.building.floors[0].map, dir_ / "a/one.yaml");
  EXPECT_EQ(BuildingOf(c.building).floors[0].map, "one");
  ASSERT_EQ(c.building.lifts.size(), 1u);
  EXPECT_EQ(c.building.lifts[0].stops[1].door.id, "east@L2");
  EXPECT_NEAR(c.building.lifts[0].stops[1].lobby.yaw_rad, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(c.mission.lifts.call_timeout_s, 30.0);
  EXPECT_EQ(c.building.controller.call.method, "PUT");
  const std::string one_floor_lift =
      ErrorOf("building: {floors: [{name: L1, map: a.yaml}], lifts: [{id: x, stops: [{floor: L1}]}]}\n");
  EXPECT_NE(one_floor_lift.find("two floors"), std::string::npos) << one_floor_lift;
  EXPECT_NE(ErrorOf("building: {floors: [{name: L1, map: a.yaml}, {name: L1, map: b.yaml}]}\n").find("twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf("building: {floors: [{name: L1}]}\n").find("building.floors[0].name, map: required"),
            std::string::npos);
}

TEST_F(ConfigTest, TrackingAndEvasionKeysAreReadAndChecked) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n"
                                    "tracking: {enabled: false, camera: false, window_scans: 6, coast_s: 0.5,"
                                    " unseen_coast_s: 3, merged_hold_s: 2, walk_end_memory_s: 20,"
                                    " traffic: {weight: 5}}\n"
                                    "mission: {max_linear_mps: 0.4, reroute_s: 5, stuck_s: 20,"
                                    " evade: {margin_m: 0.25, horizon_s: 4}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_FALSE(c.tracking.enabled);
  EXPECT_FALSE(c.tracking.camera);
  EXPECT_EQ(c.tracking.objects.window_scans, 6);
  EXPECT_DOUBLE_EQ(c.tracking.objects.coast_s, 0.5);
  EXPECT_DOUBLE_EQ(c.tracking.objects.unseen_coast_s, 3.0);
  EXPECT_DOUBLE_EQ(c.tracking.objects.merged_hold_s, 2.0);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ntracking: {coast_s: 2, merged_hold_s: 1}\n").find("tracking.merged_hold_s"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf("sim: {world: w.yaml}\ntracking: {coast_s: 2, unseen_coast_s: 1}\n").find("tracking.unseen_coast_s"),
      std::string::npos);
  EXPECT_DOUBLE_EQ(c.tracking.objects.walk_end_memory_s, 20.0);
  EXPECT_DOUBLE_EQ(c.tracking.traffic.weight, 5.0);
  EXPECT_DOUBLE_EQ(c.mission.navigator.reroute_s, 5.0);
  EXPECT_DOUBLE_EQ(c.mission.navigator.stuck_s, 20.0);
  EXPECT_DOUBLE_EQ(c.mission.navigator.evade.margin_m, 0.25);
  EXPECT_DOUBLE_EQ(c.mission.navigator.evade.horizon_s, 4.0);
  EXPECT_DOUBLE_EQ(c.mission.navigator.evade.max_linear_mps, 0.4);  // the mission's own top speed
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ntracking: {window_scans: 1}\n").find("tracking.window_scans"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\ntracking: {traffic: {memory_s: 0}}\n").find("tracking.traffic.memory_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nmission: {evade: {horizon_s: 0}}\n").find("mission.evade.horizon_s"),
            std::string::npos);
}

TEST_F(ConfigTest, ThePlannerKeepsTheGuardsMarginFromWhatTheCameraSawAtTheCostSet) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\nplanner: {layer_cost: 5}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_DOUBLE_EQ(c.planner.layer_cost, 5.0);
  EXPECT_DOUBLE_EQ(c.planner.layer_margin_m, c.mission.navigator.memory.margin_m);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nplanner: {layer_cost: -1}\n").find("planner.layer_cost"), std::string::npos);
}

TEST_F(ConfigTest, LocalizationKeysAreReadAndChecked) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n"
                                    "localization: {source: mcl, initial_sigma_m: 0.3, initial_sigma_deg: 10,"
                                    " relocalize_every_s: 5, mcl: {seed: 7, min_particles: 100, max_particles: 500,"
                                    " sigma_hit_m: 0.1, max_beams: 60, update_distance_m: 0.1, update_angle_deg: 6}}\n";
  const Config c = LoadConfig(dir_ / "c.yaml");
  EXPECT_EQ(c.localization.source, LocalizationOptions::Source::kMonteCarlo);
  EXPECT_DOUBLE_EQ(c.localization.initial_sigma_m, 0.3);
  EXPECT_DOUBLE_EQ(c.localization.initial_sigma_deg, 10.0);
  EXPECT_DOUBLE_EQ(c.localization.relocalize_every_s, 5.0);
  EXPECT_EQ(c.localization.seed, 7u);
  EXPECT_EQ(c.localization.mcl.min_particles, 100);
  EXPECT_EQ(c.localization.mcl.max_particles, 500);
  EXPECT_DOUBLE_EQ(c.localization.mcl.sigma_hit_m, 0.1);
  EXPECT_EQ(c.localization.mcl.max_beams, 60);
  EXPECT_DOUBLE_EQ(c.localization.mcl.update_distance_m, 0.1);
  EXPECT_NEAR(c.localization.mcl.update_angle_rad, 0.10472, 1e-5);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nlocalization: {source: amcl}\n")
                .find("localization.source: must be odometry, sim_truth or mcl, got 'amcl'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\nlocalization: {mcl: {min_particles: 500, max_particles: 100}}\n")
                .find("localization.mcl.max_particles: must be at least min_particles"),
            std::string::npos);
}

TEST_F(ConfigTest, SimulatedObstaclesAreAListCheckedItemByItem) {
  EXPECT_EQ(ErrorOf("sim:\n  world: w.yaml\n  obstacles:\n    - {shape: box, x_m: 1, y_m: 2, size_m: 0.3}\n"
                    "    - {x_m: 3, y_m: 2}\n"),
            "");
  const std::string shape = ErrorOf("sim:\n  world: w.yaml\n  obstacles:\n    - {x_m: 1}\n    - {shape: cone}\n");
  EXPECT_NE(shape.find("sim.obstacles[1].shape: must be cylinder, box or table"), std::string::npos) << shape;
  const std::string unknown = ErrorOf("sim:\n  world: w.yaml\n  obstacles:\n    - {radius: 1}\n");
  EXPECT_NE(unknown.find("sim.obstacles[0].radius: unknown key"), std::string::npos) << unknown;
  const std::string not_list = ErrorOf("sim:\n  world: w.yaml\n  obstacles: {x_m: 1}\n");
  EXPECT_NE(not_list.find("sim.obstacles: expected a list"), std::string::npos) << not_list;
  const std::string people = ErrorOf("sim: {world: w.yaml, pedestrians: 50}\n");
  EXPECT_NE(people.find("sim.pedestrians: must be between 0 and 20"), std::string::npos) << people;
}

TEST_F(ConfigTest, CommandLineOverridesGetTheSameChecks) {
  ConfigOverrides o;
  o.port = 70000;
  EXPECT_NE(ErrorOf("sim: {world: w.yaml}\n", o).find("server.port: must be between 0 and 65535"), std::string::npos);
  o.port = 9090;
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n";
  EXPECT_EQ(LoadConfig(dir_ / "c.yaml", o).server.port, 9090);
}

TEST_F(ConfigTest, BrokenFilesAreReported) {
  EXPECT_NE(ErrorOf("sim: {enabled: false\n").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf("- a list\n").find("expected a mapping"), std::string::npos);
  try {
    LoadConfig(dir_ / "absent.yaml");
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be opened"), std::string::npos);
  }
}

TEST(ConfigCommentsTest, AKeysHelpIsItsCommentWithItsContinuationsAfterTheBlockAboveIt) {
  const auto help = ConfigComments(
      "# The file's header.\n"
      "\n"
      "# Who may use the robot.\n"
      "#   viewer  reads\n"
      "auth:\n"
      "  open: false   # true: reads without logging in\n"
      "  name: \"a # not a comment\"\n"
      "  # Forward motion stops before\n"
      "  # what the camera sees.\n"
      "  timeout_s: 0.3   # scans older than this are stale\n"
      "                   # (an RPLIDAR turns at 5.5 Hz)\n"
      "  list:\n"
      "    - {a: 1}   # an item\n"
      "other:\n"
      "  deep:\n"
      "    leaf: 1   # a leaf\n");
  EXPECT_EQ(help.at("auth"), "Who may use the robot.\n  viewer  reads");
  EXPECT_EQ(help.at("auth.open"), "true: reads without logging in");
  EXPECT_FALSE(help.contains("auth.name"));
  EXPECT_EQ(help.at("auth.timeout_s"),
            "Forward motion stops before what the camera sees.\n"
            "scans older than this are stale (an RPLIDAR turns at 5.5 Hz)");
  EXPECT_EQ(help.at("other.deep.leaf"), "a leaf");
  EXPECT_FALSE(help.contains("auth.list.a"));
}

TEST(ConfigCommentsTest, UnitsComeFromTheKeysSuffix) {
  EXPECT_EQ(UnitOfKey("max_linear_mps"), "m/s");
  EXPECT_EQ(UnitOfKey("max_decel_mps2"), "m/s²");
  EXPECT_EQ(UnitOfKey("odometry_timeout_s"), "s");
  EXPECT_EQ(UnitOfKey("mount_yaw_deg"), "°");
  EXPECT_EQ(UnitOfKey("port"), "");
  EXPECT_EQ(UnitOfKey("_s"), "");
}

TEST_F(ConfigTest, TheSchemaIsWhatTheCheckingCodeReadsWithTheShippedFilesHelp) {
  std::ofstream(dir_ / "c.yaml") << "sim: {world: w.yaml}\n"
                                    "safety: {max_linear_mps: 0.3}\n";
  const nlohmann::json schema = ConfigSchemaJson(dir_ / "c.yaml");
  const auto field = [&](const std::string& path) {
    for (const auto& f : schema["fields"]) {
      if (f["path"] == path) return f;
    }
    ADD_FAILURE() << path << " is not in the schema";
    return nlohmann::json();
  };
  const auto speed = field("safety.max_linear_mps");
  EXPECT_EQ(speed["type"], "number");
  EXPECT_EQ(speed["default"], 0.5);  // the code's, not the file's
  EXPECT_EQ(speed["min"], 0.0);
  EXPECT_EQ(speed["max"], 3.0);
  EXPECT_EQ(speed["unit"], "m/s");
  EXPECT_EQ(field("server.port")["type"], "integer");
  EXPECT_EQ(field("server.port")["help"], "0 picks a free port");
  EXPECT_EQ(field("auth.anonymous_viewer")["type"], "boolean");
  EXPECT_EQ(field("log.level")["choices"], nlohmann::json({"trace", "debug", "info", "warn", "error"}));
  EXPECT_NE(schema["sections"]["auth"].get<std::string>().find("Who may use the robot"), std::string::npos);
  // Every key the shipped file sets is described, with help.
  std::size_t undocumented = 0;
  for (const auto& f : schema["fields"]) undocumented += f["help"].get<std::string>().empty() ? 1 : 0;
  EXPECT_LT(undocumented, schema["fields"].size());
}

}  // namespace
}  // namespace corridor::server
