// Doors on the way through the daemon's graph in simulated time (testing/lockstep_robot.h): two rooms joined by a
// doorway with a closed simulated door in it, and no doors.controller, so the simulator's doors answer
// (SimDoorController: a door asked open swings open 2 s later). A mission to the other room asks for the door, waits
// short of it until it is open, passes, arrives and releases it, and the door closes behind the robot; the robot never
// touches the closed door. (The controllers' transports, HTTP and Open-RMF over MQTT, and a door that refuses or a
// controller that stops answering are tests/doors_test.mjs.)
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "testing/lockstep_robot.h"
#include "testing/temp_dir.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
namespace fs = std::filesystem;

constexpr double kWallX = 4.0;  // the wall between the rooms, its doorway at y 1..2

// An 8 x 3 m map split by a wall at x = 4 with a 1 m doorway, and the simulator in it with its door d1 (closed) in the
// doorway and the robot in the left room.
class TwoRooms {
 public:
  TwoRooms() {
    const double res = 0.05;
    const int w = static_cast<int>(std::lround(8 / res)) + 2;
    const int h = static_cast<int>(std::lround(3 / res)) + 2;
    std::vector<char> pixels(static_cast<std::size_t>(w) * h, static_cast<char>(254));
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        const double x = (col - 1 + 0.5) * res;
        const double y = (h - 1 - row - 1 + 0.5) * res;
        const bool border = row == 0 || col == 0 || row == h - 1 || col == w - 1;
        const bool wall = std::abs(x - kWallX) < 0.05 && (y < 1.0 || y > 2.0);
        if (border || wall) pixels[static_cast<std::size_t>(row) * w + col] = 0;
      }
    }
    std::ofstream pgm(dir_.path() / "rooms.pgm", std::ios::binary);
    pgm << "P5\n" << w << " " << h << "\n255\n";
    pgm.write(pixels.data(), static_cast<std::streamsize>(pixels.size()));
    std::ofstream(dir_.path() / "rooms.yaml")
        << "image: rooms.pgm\nresolution: 0.05\norigin: [-0.05, -0.05, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
           "free_thresh: 0.196\n";
    std::ofstream(config()) << "sim:\n"
                               "  world: \""
                            << (dir_.path() / "rooms.yaml").string()
                            << "\"\n"
                               "  start: {x_m: 2.0, y_m: 1.5, yaw_deg: 0}\n"
                               "  camera: {width: 160, height: 120}\n"
                               "  dock: {enabled: false}\n"
                               "  doors:\n"
                               "    - {id: d1, x1_m: 4.0, y1_m: 1.0, x2_m: 4.0, y2_m: 2.0}\n";
  }
  fs::path config() const { return dir_.path() / "corridor.yaml"; }

 private:
  testing::TempDir dir_{"corridor_doors"};
};

bool DoorOpen(LockstepRobot& robot) { return robot.Call("GET", "/api/v1/sim/doors").body["doors"][0]["open"]; }

TEST(DoorsLockstep, AMissionThroughTheDoorWaitsForItPassesAndReleasesIt) {
  TwoRooms rooms;
  LockstepRobot robot(rooms.config());
  robot.StepFor(1.0);
  const json listed = robot.Call("GET", "/api/v1/doors").body;
  EXPECT_EQ(listed["controlled"], true) << listed.dump();
  ASSERT_FALSE(DoorOpen(robot));

  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", 6.0}, {"y", 1.5}}})}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  const std::string url = "/api/v1/missions/" + started.body["id"].get<std::string>();

  // Short of the door, waiting for it, while it is still closed.
  json mission;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        mission = robot.Call("GET", url).body;
        return mission.value("waiting_for_door", "") == "d1";
      },
      30.0))
      << mission.dump();
  EXPECT_EQ(mission["policy"], "waiting_for_door");
  EXPECT_FALSE(DoorOpen(robot));
  const double robot_radius_m = robot.config().planner.robot_radius_m;
  EXPECT_LT(robot.State()["sim_true_pose"]["x"].get<double>(), kWallX - robot_radius_m - 0.05);

  // Through once it opens, never touching the closed door: the footprint is never across its line while it is shut.
  bool touched = false;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        const json state = robot.State();
        const double x = state["sim_true_pose"]["x"].get<double>();
        if (!DoorOpen(robot) && std::abs(x - kWallX) < robot_radius_m) touched = true;
        mission = robot.Call("GET", url).body;
        return mission["status"] != "active";
      },
      90.0))
      << mission.dump();
  EXPECT_FALSE(touched);
  EXPECT_EQ(mission["status"], "succeeded") << mission.dump();
  const json pose = robot.State()["sim_true_pose"];
  EXPECT_LT(std::hypot(pose["x"].get<double>() - 6.0, pose["y"].get<double>() - 1.5), 0.1) << pose.dump();

  // Released behind the robot: the door it opened closes.
  EXPECT_TRUE(robot.StepUntil([&] { return !DoorOpen(robot); }, 10.0));
  // Building systems were told the mission waited for the door (GET /api/v1/events, as webhooks are).
  const json events = robot.Call("GET", "/api/v1/events").body["events"];
  const auto waited = std::find_if(events.begin(), events.end(), [](const json& e) { return e["type"] == "waiting"; });
  ASSERT_NE(waited, events.end()) << events.dump();
  EXPECT_EQ((*waited)["data"]["detail"], "door d1 to open");
  EXPECT_EQ((*waited)["data"]["mission_id"], started.body["id"]);
}

}  // namespace
}  // namespace corridor
