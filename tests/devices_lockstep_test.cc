// The devices' health through the daemon's graph in simulated time (testing/lockstep_robot.h): every device of the
// simulator's robot reported ok at its rate, the laser's latest scan readable, and a camera that stops sending frames
// reported stale while the robot holds its forward motion; a robot without a laser has no scan to give; a robot without
// a camera drives on its laser's lanes and stops short of a wall. And the calibrations: the camera's mounting from the
// floor, the laser's yaw against the camera, the wheels from a straight run and a turn.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "server/runtime/topics.h"
#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"

namespace corridor {
namespace {

using json = nlohmann::json;
using testing::LockstepRobot;
using testing::ShippedConfig;

json Device(const json& health, const std::string& name) {
  for (const json& d : health["devices"]) {
    if (d["device"] == name) return d;
  }
  return nullptr;
}

TEST(DevicesLockstep, TheSimulatorsDevicesAreOkAtTheirRatesAndAStoppedCameraIsStale) {
  LockstepRobot robot(ShippedConfig());
  robot.StepFor(3.0);
  const LockstepRobot::Reply health = robot.Call("GET", "/api/v1/devices");
  ASSERT_EQ(health.status, 200) << health.body.dump();
  ASSERT_EQ(health.body["devices"].size(), 3u) << health.body.dump();
  const auto rate = [&](const std::string& name) { return Device(health.body, name)["rate_hz"].get<double>(); };
  for (const char* name : {"base", "laser", "camera"}) {
    EXPECT_EQ(Device(health.body, name)["state"], "ok") << health.body.dump();
    EXPECT_EQ(Device(health.body, name)["driver"], "sim");
    EXPECT_TRUE(Device(health.body, name)["link"].is_null());  // the simulator watches no link
  }
  EXPECT_NEAR(rate("base"), robot.config().sim.robot.odometry_rate_hz, 2.0);
  EXPECT_NEAR(rate("laser"), robot.config().sim.robot.laser.rate_hz, 1.0);
  EXPECT_NEAR(rate("camera"), robot.config().sim.robot.camera.rate_hz, 1.0);
  EXPECT_EQ(robot.State()["devices"].size(), 3u);
  // Handing each device's data to the graph took time on the thread that delivered it (here the test's own), and
  // takes more as more comes.
  const auto handoff = [&](const json& body, const std::string& name) {
    return Device(body, name)["handoff_cpu_s"].get<double>();
  };
  for (const char* name : {"base", "laser", "camera"}) EXPECT_GT(handoff(health.body, name), 0.0) << name;
  robot.StepFor(1.0);
  EXPECT_GT(handoff(robot.Call("GET", "/api/v1/devices").body, "camera"), handoff(health.body, "camera"));

  const LockstepRobot::Reply scan = robot.Call("GET", "/api/v1/laser/scan");
  ASSERT_EQ(scan.status, 200);
  EXPECT_EQ(scan.body["frame"], "laser");
  EXPECT_EQ(scan.body["ranges"].size(), static_cast<std::size_t>(robot.config().sim.robot.laser.beams));

  // Driving forward; then the camera stops: forward motion holds, and the camera is stale.
  const json forward{{"linear_mps", 0.3}, {"angular_rps", 0.0}};
  ASSERT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"camera_stopped", true}}).status, 200);
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        robot.Call("POST", "/api/v1/teleop", forward);
        return robot.State()["stop_reason"] == "no depth frames: not driving forward";
      },
      2.0));
  EXPECT_EQ(robot.State()["command"]["linear_mps"], 0.0);
  EXPECT_TRUE(robot.StepUntil(
      [&] { return Device(robot.Call("GET", "/api/v1/devices").body, "camera")["state"] == "stale"; }, 1.0));
  ASSERT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"camera_stopped", false}}).status, 200);
  EXPECT_TRUE(robot.StepUntil(
      [&] {
        robot.Call("POST", "/api/v1/teleop", forward);
        return robot.State()["command"]["linear_mps"].get<double>() > 0.0;
      },
      2.0));
}

TEST(DevicesLockstep, ARobotWithoutALaserHasNoScanToGive) {
  LockstepRobot robot(ShippedConfig(), [](server::Config& c) { c.devices.laser.driver = server::DeviceDriver::kNone; });
  robot.StepFor(1.0);
  EXPECT_EQ(robot.Call("GET", "/api/v1/laser/scan").status, 404);
  EXPECT_EQ(robot.Call("GET", "/api/v1/devices").body["devices"].size(), 2u);
}

TEST(DevicesLockstep, ARobotWithoutACameraStopsShortOfAWallOnItsLasersLanes) {
  LockstepRobot robot(ShippedConfig(),
                      [](server::Config& c) { c.devices.camera.driver = server::DeviceDriver::kNone; });
  robot.StepFor(1.0);
  const json devices = robot.Call("GET", "/api/v1/devices").body;
  ASSERT_EQ(devices["devices"].size(), 2u) << devices.dump();
  EXPECT_TRUE(Device(devices, "camera").is_null());
  EXPECT_FALSE(robot.graph().bus().Get(server::topics::kRgbd).latest());  // nothing renders depth for nobody
  EXPECT_EQ(robot.Call("GET", "/api/v1/camera/depth").status, 404);

  // Down the corridor ahead, at 0.3 m/s by hand: the laser's lanes slow the robot to a stop before the wall across it
  // (the map's specks at y = 26 m), and it never bumps.
  const json forward{{"linear_mps", 0.3}, {"angular_rps", 0.0}};
  double last_teleop_s = -1.0;
  const auto drive = [&] {
    if (robot.now_s() - last_teleop_s >= 0.1) {
      robot.Call("POST", "/api/v1/teleop", forward);
      last_teleop_s = robot.now_s();
    }
  };
  const nav::Pose2 start = robot.sim().true_pose();
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        drive();
        const json state = robot.State();
        return robot.sim().true_pose().y_m - start.y_m > 0.5 && state["command"]["linear_mps"] == 0.0 &&
               state["stop_reason"] == "slowed for an obstacle ahead";
      },
      90.0))
      << robot.State().dump();
  EXPECT_FALSE(robot.graph().bus().Get(server::topics::kBumped).latest());
  EXPECT_FALSE(robot.sim().bumper_pressed());
}

// What is plugged in: this machine's serial ports, video nodes and OpenNI2 devices (here, none of any: the lists are
// empty, and answer all the same).
TEST(DevicesLockstep, WhatIsPluggedInIsListed) {
  LockstepRobot robot(ShippedConfig());
  const LockstepRobot::Reply hardware = robot.Call("GET", "/api/v1/devices/hardware");
  ASSERT_EQ(hardware.status, 200) << hardware.body.dump();
  for (const char* kind : {"serial", "video", "openni2"}) {
    ASSERT_TRUE(hardware.body[kind].is_array()) << hardware.body.dump();
  }
  for (const json& port : hardware.body["serial"]) EXPECT_TRUE(port["path"].get<std::string>().starts_with("/dev/tty"));
}

// The camera's mounting measured from the floor in its latest frame: the simulator's camera sits 0.3 m up, tilted
// 10 degrees down, and the measurement says so, with the configuration's keys to keep it.
TEST(DevicesLockstep, TheCamerasHeightAndTiltAreMeasuredFromTheFloor) {
  LockstepRobot robot(ShippedConfig());
  robot.StepFor(0.5);
  const LockstepRobot::Reply fit = robot.Call("POST", "/api/v1/devices/camera/calibration", json::object());
  ASSERT_EQ(fit.status, 200) << fit.body.dump();
  EXPECT_NEAR(fit.body["height_m"].get<double>(), 0.3, 0.02) << fit.body.dump();
  EXPECT_NEAR(fit.body["tilt_deg"].get<double>(), 10.0, 1.0) << fit.body.dump();
  EXPECT_NEAR(fit.body["roll_deg"].get<double>(), 0.0, 1.0) << fit.body.dump();
  EXPECT_NEAR(fit.body["configured"]["tilt_deg"].get<double>(), 10.0, 1e-6);
  EXPECT_NEAR(fit.body["patch"]["sim"]["camera"]["mount_height_m"].get<double>(), 0.3, 0.02);
  // A robot without a camera has nothing to measure.
  LockstepRobot blind(ShippedConfig(),
                      [](server::Config& c) { c.devices.camera.driver = server::DeviceDriver::kNone; });
  EXPECT_EQ(blind.Call("POST", "/api/v1/devices/camera/calibration", json::object()).status, 404);
}

// The laser's yaw against the camera: the configuration says the simulator's laser is turned 4 degrees, it faces
// forward, and laying its scan on the camera's view says so.
TEST(DevicesLockstep, TheLasersYawIsMeasuredAgainstTheCamera) {
  LockstepRobot robot(ShippedConfig(), [](server::Config& c) { c.sim.robot.laser.mount_yaw_deg = 4.0; });
  robot.StepFor(0.5);
  const LockstepRobot::Reply fit = robot.Call("POST", "/api/v1/devices/laser/calibration", json::object());
  ASSERT_EQ(fit.status, 200) << fit.body.dump();
  EXPECT_NEAR(fit.body["yaw_deg"].get<double>(), 0.0, 0.5) << fit.body.dump();
  EXPECT_NEAR(fit.body["configured"]["yaw_deg"].get<double>(), 4.0, 1e-9);
  EXPECT_GT(fit.body["points"].get<int>(), 20);
  EXPECT_NEAR(fit.body["patch"]["sim"]["laser"]["mount_yaw_deg"].get<double>(), 0.0, 0.5);
  std::printf("the laser's yaw: configured 4.0 degrees, measured %.2f (truly 0)\n", fit.body["yaw_deg"].get<double>());
  // Moving, it does not measure; without a camera, there is nothing to measure against.
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        robot.Call("POST", "/api/v1/teleop", {{"linear_mps", 0.0}, {"angular_rps", 0.5}});
        const auto odometry = robot.graph().bus().Get(server::topics::kOdometry).latest();
        return odometry && std::abs(odometry->velocity.angular_rps) > 0.1;
      },
      2.0));
  EXPECT_EQ(robot.Call("POST", "/api/v1/devices/laser/calibration", json::object()).status, 409);
  LockstepRobot blind(ShippedConfig(),
                      [](server::Config& c) { c.devices.camera.driver = server::DeviceDriver::kNone; });
  blind.StepFor(0.5);
  EXPECT_EQ(blind.Call("POST", "/api/v1/devices/laser/calibration", json::object()).status, 404);
}

// The wheels: the simulator's odometry counts with a wheel diameter 4 % too large and a track 3 % too small. A straight
// run towards the wall ahead measures the diameter, a turn on the spot the track, and the patches undo both errors.
TEST(DevicesLockstep, TheWheelsDiameterAndTrackAreMeasuredFromAStraightRunAndATurn) {
  LockstepRobot robot(ShippedConfig(), [](server::Config& c) {
    c.sim.robot.base.wheel_diameter_error = 1.04;
    c.sim.robot.base.track_error = 0.97;
  });
  robot.StepFor(0.5);
  EXPECT_EQ(robot.Call("POST", "/api/v1/devices/wheels/calibration/finish", json::object()).status,
            409);  // not started
  // Drives by hand (the console's keys) until `done`, then stands a second for a scan taken still.
  const auto run = [&](const json& twist, const std::function<bool()>& done) {
    ASSERT_EQ(robot.Call("POST", "/api/v1/devices/wheels/calibration/start", json::object()).status, 200);
    double last_s = -1.0;
    ASSERT_TRUE(robot.StepUntil(
        [&] {
          if (robot.now_s() - last_s >= 0.1) {
            robot.Call("POST", "/api/v1/teleop", twist);
            last_s = robot.now_s();
          }
          return done();
        },
        20.0));
    robot.StepFor(1.0);
  };
  const nav::Pose2 start = robot.sim().true_pose();
  run({{"linear_mps", 0.25}, {"angular_rps", 0.0}},
      [&] { return (robot.sim().true_pose().translation() - start.translation()).norm() > 0.8; });
  const LockstepRobot::Reply straight = robot.Call("POST", "/api/v1/devices/wheels/calibration/finish", json::object());
  ASSERT_EQ(straight.status, 200) << straight.body.dump();
  EXPECT_EQ(straight.body["run"], "straight");
  const double travelled = (robot.sim().true_pose().translation() - start.translation()).norm();
  EXPECT_NEAR(straight.body["measured"].get<double>(), travelled, 0.02) << straight.body.dump();
  EXPECT_NEAR(straight.body["diameter_factor"].get<double>(), 1.0 / 1.04, 0.01) << straight.body.dump();
  EXPECT_NEAR(straight.body["patch"]["sim"]["base"]["wheel_diameter_error"].get<double>(), 1.0, 0.01);

  const double yaw0 = robot.sim().true_pose().yaw_rad;
  run({{"linear_mps", 0.0}, {"angular_rps", 0.6}},
      [&] { return nav::WrapAngle(robot.sim().true_pose().yaw_rad - yaw0) > 2.4; });
  const LockstepRobot::Reply turn = robot.Call("POST", "/api/v1/devices/wheels/calibration/finish", json::object());
  ASSERT_EQ(turn.status, 200) << turn.body.dump();
  EXPECT_EQ(turn.body["run"], "turn");
  const double turned_deg = nav::WrapAngle(robot.sim().true_pose().yaw_rad - yaw0) * 180.0 / M_PI;
  EXPECT_NEAR(turn.body["measured"].get<double>(), turned_deg, 1.0) << turn.body.dump();
  EXPECT_NEAR(turn.body["track_factor"].get<double>(), 1.0 / 0.97, 0.01) << turn.body.dump();
  EXPECT_NEAR(turn.body["patch"]["sim"]["base"]["track_error"].get<double>(), 1.0, 0.01);
  EXPECT_NEAR(turn.body["patch"]["sim"]["base"]["wheel_diameter_error"].get<double>(), 1.0, 0.01);
  std::printf(
      "the wheels: diameter factor %.4f (truly %.4f), track factor %.4f (truly %.4f); %.3f m and %.1f degrees "
      "measured, %.3f m and %.1f truly\n",
      straight.body["diameter_factor"].get<double>(), 1.0 / 1.04, turn.body["track_factor"].get<double>(), 1.0 / 0.97,
      straight.body["measured"].get<double>(), turn.body["measured"].get<double>(), travelled, turned_deg);
}

}  // namespace
}  // namespace corridor
