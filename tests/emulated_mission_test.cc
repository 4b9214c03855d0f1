// A mission through native drivers, end to end: corridord drives the simulated robot of the default world through
// a Create 2 and an RPLIDAR served on pseudo-terminals by testing/emulated_robot.h (corridor-emulate's), with no
// camera: the laser's lanes steer it, its scans localize it in the world's map, the Create 2's encoders give its
// odometry. The transport is the point (real serial ports, a real daemon): real time.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "server/config/config.h"
#include "testing/emulated_robot.h"
#include "testing/eventually.h"
#include "tests/dds/ros2_fixtures.h"

namespace corridor::testing {
namespace {

using json = nlohmann::json;
using namespace std::chrono_literals;

TEST(EmulatedMission, CorridordRunsAMissionThroughACreate2AndAnRplidarWithoutACamera) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("corridor-emulated-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string devices = "  base: {driver: create2, port: " + (dir / "create2").string() + "}\n" +
                              "  laser: {driver: rplidar, port: " + (dir / "rplidar").string() + "}\n" +
                              "  camera: {driver: none}\n";
  const std::string config = DdsConfig(CORRIDOR_SOURCE_DIR, -1, false, "", devices, /*laser_localization=*/true);
  ASSERT_FALSE(config.empty());
  std::ofstream(dir / "corridor.yaml") << config;
  EmulatedRobot robot(server::LoadConfig(dir / "corridor.yaml"), dir / "create2", dir / "rplidar");
  DaemonProcess daemon(CORRIDORD, CORRIDOR_SOURCE_DIR, -1, false, "", devices, /*laser_localization=*/true);

  const auto localization = [&] { return daemon.Call("GET", "/api/v1/localization").second; };
  ASSERT_TRUE(Eventually(
      [&] {
        const json devices_now = daemon.Call("GET", "/api/v1/devices").second["devices"];
        bool ok = devices_now.size() == 2;
        for (const json& d : devices_now) ok = ok && d["state"] == "ok";
        return ok && localization().value("health", "") == "ok";
      },
      30s))
      << daemon.Call("GET", "/api/v1/devices").second.dump() << localization().dump() << daemon.log();

  // Down the corridor west of the start and back (docs/hardware.md: goals in the open for a laser robot).
  const json waypoints = json::array({{{"x", 22.5}, {"y", 24.3}}, {{"x", 24.0}, {"y", 24.3}}});
  const auto [status, started] = daemon.Call("POST", "/api/v1/missions", {{"waypoints", waypoints}});
  ASSERT_EQ(status, 201) << started.dump();
  const std::string id = started["id"].get<std::string>();
  json mission;
  ASSERT_TRUE(Eventually(
      [&] {
        mission = daemon.Call("GET", "/api/v1/missions/" + id).second;
        return mission.value("status", "") != "active";
      },
      90s))
      << mission.dump();
  EXPECT_EQ(mission["status"], "succeeded") << mission.dump() << daemon.log();
  // Where the simulator's truth has the robot: at the last waypoint, having hit nothing on the way.
  const nav::Pose2 truth = robot.true_pose();
  EXPECT_NEAR(truth.x_m, 24.0, 0.3);
  EXPECT_NEAR(truth.y_m, 24.3, 0.3);
  EXPECT_FALSE(robot.bumped());
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

}  // namespace
}  // namespace corridor::testing
