// corridord on native drivers, as on a robot built from a Create 2 and an RPLIDAR (tests/dds/native_robot.h: both on
// pseudo-terminals played by their emulators, the depth camera a ROS 2 driver over DDS, so the slots mix as devices.*
// allows). The transport is the point (real serial ports, a real daemon): the devices report ok with their rates, the
// laser's scan is readable, teleop turns the emulated wheels, and a laser that goes quiet, a cliff, or a laser
// unplugged and plugged back in stops the robot until it is back. And each other base (Kobuki, TurtleBot 3, a home-made
// base's Arduino) with an RPLIDAR and no camera, driven the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "testing/emulators/kobuki_emulator.h"
#include "testing/emulators/opencr_emulator.h"
#include "testing/emulators/serial_text_emulator.h"
#include "testing/eventually.h"
#include "tests/dds/native_robot.h"

namespace corridor::testing {
namespace {

using json = nlohmann::json;
using namespace std::chrono_literals;

TEST(NativeDevices, ACreate2AndAnRplidarDriveTheRobotAndADeviceGoneStopsIt) {
  NativeRobot robot(CORRIDORD, CORRIDOR_SOURCE_DIR, Domain(10));
  DaemonProcess& daemon = robot.daemon();
  const auto moving = [&] { return robot.moving(); };
  const auto still = [&] { return robot.still(); };
  const auto state = [&](const char* key) { return daemon.Call("GET", "/api/v1/state").second.value(key, ""); };

  ASSERT_TRUE(robot.Until(false, 20s, [&] { return robot.AllOk(); }))
      << daemon.Call("GET", "/api/v1/devices").second.dump() << daemon.log();
  // Each device's rate, once a couple of seconds have been counted: the RPLIDAR's 10 turns a second; the Create 2's
  // odometry, one report for each pass of the control loop that found frames (its 50 Hz tick; a frame every 15 ms).
  EXPECT_TRUE(robot.Until(false, 5s, [&] { return std::abs(robot.Rate("laser") - 10.0) < 2.0; }))
      << robot.Rate("laser");
  EXPECT_TRUE(robot.Until(false, 5s, [&] { return std::abs(robot.Rate("base") - 55.0) < 15.0; })) << robot.Rate("base");
  const json health = daemon.Call("GET", "/api/v1/devices").second;
  for (const json& d : health["devices"]) {
    if (d["device"] == "laser") {
      EXPECT_EQ(d["driver"], "rplidar");
      EXPECT_EQ(d["link"], "running");
    }
  }
  // The laser's scan in its own frame (REP-103), 2 m all round as the emulator measures.
  const auto [scan_status, scan] = daemon.Call("GET", "/api/v1/laser/scan");
  ASSERT_EQ(scan_status, 200) << scan.dump();
  EXPECT_EQ(scan["frame"], "laser");
  EXPECT_NEAR(scan["base_T_laser"]["yaw"].get<double>(), M_PI, 1e-6) << scan.dump();
  int near_two = 0;
  for (const json& r : scan["ranges"]) near_two += r.is_number() && std::abs(r.get<double>() - 2.0) < 0.05;
  EXPECT_GT(near_two, 300) << scan.dump();

  // Teleop turns the Create 2's wheels.
  ASSERT_TRUE(robot.Until(true, 10s, moving)) << state("stop_reason") << daemon.log();

  // The laser goes quiet: the robot stops, says why, and the device is stale; it drives again once scans are back.
  robot.laser().Silence();
  ASSERT_TRUE(robot.Until(true, 3s, still)) << daemon.log();
  EXPECT_NE(state("stop_reason").find("laser (rplidar on"), std::string::npos) << state("stop_reason");
  EXPECT_TRUE(robot.Until(true, 3s, [&] { return robot.DeviceState("laser") != "ok"; }));
  EXPECT_TRUE(robot.Until(true, 5s, [&] { return state("face") == "sad"; }));
  robot.laser().Resume();
  ASSERT_TRUE(robot.Until(true, 10s, moving)) << state("stop_reason") << daemon.log();

  // A cliff under the base: stopped at once, whatever is asked.
  robot.base().SetCliff(true);
  ASSERT_TRUE(robot.Until(true, 3s, still)) << daemon.log();
  EXPECT_TRUE(robot.Until(true, 3s, [&] { return state("stop_reason").find("cliff") != std::string::npos; }))
      << state("stop_reason");
  robot.base().SetCliff(false);
  ASSERT_TRUE(robot.Until(true, 10s, moving)) << state("stop_reason") << daemon.log();

  // The laser unplugged: stopped, disconnected; plugged back in under the same path, it is taken up by itself.
  robot.laser().Unplug();
  ASSERT_TRUE(robot.Until(true, 3s, still)) << daemon.log();
  EXPECT_TRUE(robot.Until(true, 3s, [&] { return robot.DeviceState("laser") == "disconnected"; }))
      << daemon.Call("GET", "/api/v1/devices").second.dump();
  robot.laser().Replug();
  ASSERT_TRUE(robot.Until(true, 15s, moving)) << state("stop_reason") << daemon.log();
  EXPECT_TRUE(robot.Until(false, 5s, [&] { return robot.AllOk(); }));

  EXPECT_TRUE(daemon.Stop()) << daemon.log();
  EXPECT_TRUE(robot.Until(false, 2s, still));  // the driver stopped the wheels on its way out
}

// A base of each protocol with an RPLIDAR and no camera (the laser's lanes its sight): a TurtleBot 2's Kobuki, a
// TurtleBot 3's OpenCR, a home-made base's Arduino. Teleop turns the emulated wheels; the base unplugged stops the
// robot, and it drives again once plugged back in.
struct EmulatedBase {
  std::function<std::pair<double, double>()> wheels_mps;
  std::function<void()> unplug;
  std::function<void()> replug;
};

class NativeBases : public ::testing::TestWithParam<std::string> {};

TEST_P(NativeBases, ABaseWithAnRplidarAndNoCameraDrives) {
  const std::string driver = GetParam();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("corridor-base-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path port = dir / "base";
  std::string base_options;
  std::unique_ptr<KobukiEmulator> kobuki;
  std::unique_ptr<OpenCrEmulator> opencr;
  std::unique_ptr<SerialTextEmulator> arduino;
  EmulatedBase base;
  if (driver == "kobuki") {
    kobuki = std::make_unique<KobukiEmulator>(port);
    base = {[&] { return kobuki->wheels_mps(); }, [&] { kobuki->Unplug(); }, [&] { kobuki->Replug(); }};
  } else if (driver == "turtlebot3") {
    opencr = std::make_unique<OpenCrEmulator>(port);
    base = {[&] { return opencr->wheels_mps(); }, [&] { opencr->Unplug(); }, [&] { opencr->Replug(); }};
  } else {
    arduino = std::make_unique<SerialTextEmulator>(port);  // the emulator's wheels
    base_options = ", wheel_diameter_m: 0.065, track_m: 0.2, counts_per_revolution: 1920";
    base = {[&] { return arduino->wheels_mps(); }, [&] { arduino->Unplug(); }, [&] { arduino->Replug(); }};
  }
  RplidarEmulator laser(dir / "rplidar", RplidarEmulatorOptions{});
  const std::string devices = "  base: {driver: " + driver + ", port: " + port.string() + base_options + "}\n" +
                              "  laser: {driver: rplidar, port: " + (dir / "rplidar").string() + "}\n" +
                              "  camera: {driver: none}\n";
  DaemonProcess daemon(CORRIDORD, CORRIDOR_SOURCE_DIR, -1, false, "", devices);
  const auto forward = [&] {
    daemon.Call("POST", "/api/v1/teleop", {{"linear_mps", 0.15}, {"angular_rps", 0.0}});
    return base.wheels_mps().first > 0.1 && base.wheels_mps().second > 0.1;
  };
  ASSERT_TRUE(Eventually(
      [&] {
        // 503 until the devices' health is first reported: a problem without "devices".
        const json d = daemon.Call("GET", "/api/v1/devices").second.value("devices", json::array());
        return d.size() == 2 && d[0].value("state", "") == "ok" && d[1].value("state", "") == "ok";
      },
      20s))
      << daemon.Call("GET", "/api/v1/devices").second.dump() << daemon.log();
  EXPECT_EQ(daemon.Call("GET", "/api/v1/devices").second["devices"][0]["driver"], driver);
  // The emulated laser sees 2 m all round: room enough to drive forward slowly.
  ASSERT_TRUE(Eventually(forward, 10s)) << daemon.Call("GET", "/api/v1/state").second.value("stop_reason", "")
                                        << daemon.log();
  // Unplugged: the daemon stops commanding, and says the base is gone.
  base.unplug();
  EXPECT_TRUE(Eventually(
      [&] {
        json state = daemon.Call("GET", "/api/v1/state").second;  // not const: a key missing reads as null
        return state["command"]["linear_mps"] == 0.0 && state["devices"][0]["state"] != "ok";
      },
      5s))
      << daemon.Call("GET", "/api/v1/state").second.dump();
  base.replug();  // its wheels stopped, as a base powered up anew
  ASSERT_TRUE(Eventually(forward, 15s)) << daemon.log();
  EXPECT_TRUE(daemon.Stop()) << daemon.log();
  EXPECT_TRUE(Eventually([&] { return base.wheels_mps() == std::make_pair(0.0, 0.0); }, 2s));
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

INSTANTIATE_TEST_SUITE_P(EachProtocol, NativeBases, ::testing::Values("kobuki", "turtlebot3", "serial-text"),
                         [](const auto& instance) {
                           return instance.param == "serial-text" ? std::string("serial_text") : instance.param;
                         });

}  // namespace
}  // namespace corridor::testing
