// Lift rides through the daemon's graph in simulated time (testing/lockstep_robot.h): a building of two floors made of
// two bundled maps (L1: the Willow Garage office; L2: the small house) with a lift between them, whose controller is
// the simulator's own (no building.controller). A mission from L1 to a place on L2 calls the lift, boards, rides,
// switches to L2's map with the pose the car carried over, leaves and arrives, localized within centimetres of the
// truth; cancelled while riding, the robot still gets out on the floor it asked for. (The controllers' transports,
// HTTP and Open-RMF over MQTT, and a lift that refuses are tests/lifts_test.mjs.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"
#include "testing/temp_dir.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
using testing::SourceDir;
namespace fs = std::filesystem;

// The building's configuration, in a directory of its own; removed with it. The robot starts 1.5 m from the lift's
// lobby on L1.
class TwoFloors {
 public:
  TwoFloors() {
    const fs::path worlds = SourceDir() / "config/worlds";
    std::ofstream(dir_.path() / "corridor.yaml")
        << "building:\n"
           "  name: two floors\n"
           "  floors:\n"
           "    - {name: L1, map: \""
        << (worlds / "willow_garage/willow-full-0.05.yaml").string()
        << "\"}\n"
           "    - {name: L2, map: \""
        << (worlds / "small_house/maps/map.yaml").string()
        << "\"}\n"
           "  lifts:\n"
           "    - id: lift1\n"
           "      stops:\n"
           "        - {floor: L1, x1_m: 18.1, y1_m: 21.55, x2_m: 18.1, y2_m: 22.45,\n"
           "           lobby_x_m: 18.9, lobby_y_m: 22.0, lobby_yaw_deg: 180}\n"
           "        - {floor: L2, x1_m: 2.9, y1_m: 0.55, x2_m: 2.9, y2_m: 1.45, lobby_x_m: 2.1, lobby_y_m: 1.0,"
           " lobby_yaw_deg: 0}\n"
           "  sim: {travel_s: 3}\n"
           "localization: {source: mcl}\n"
           "sim:\n"
           "  start: {x_m: 20.4, y_m: 22.0, yaw_deg: 180}\n"
           "  camera: {width: 160, height: 120}\n"
           "  dock: {enabled: false}\n";
  }
  fs::path config() const { return dir_.path() / "corridor.yaml"; }

 private:
  testing::TempDir dir_{"corridor_lifts"};
};

std::string Status(const json& mission) { return mission.is_object() ? mission["status"].get<std::string>() : ""; }

// Steps until the mission `id` is over, collecting the lift phases it reports; the mission as it ended.
json UntilOver(LockstepRobot& robot, const std::string& id, double max_s, std::set<std::string>& phases) {
  json mission;
  robot.StepUntil(
      [&] {
        mission = robot.Call("GET", "/api/v1/missions/" + id).body;
        if (mission.contains("lift")) phases.insert(mission["lift"].get<std::string>());
        return Status(mission) != "active";
      },
      max_s);
  return mission;
}

void ExpectOnL2At(LockstepRobot& robot, double x, double y) {
  const json state = robot.State();
  EXPECT_EQ(state["floor"], "L2");
  EXPECT_EQ(state["map"]["name"], "map");
  const json& truth = state["sim_true_pose"];
  EXPECT_LT(std::hypot(truth["x"].get<double>() - x, truth["y"].get<double>() - y), 0.15) << truth.dump();
  const json& pose = state["pose"];
  EXPECT_LT(std::hypot(pose["x"].get<double>() - truth["x"].get<double>(),
                       pose["y"].get<double>() - truth["y"].get<double>()),
            0.15)
      << pose.dump() << " against the truth " << truth.dump();
}

bool Localized(LockstepRobot& robot) {
  const json l = robot.Call("GET", "/api/v1/localization").body;
  return l.is_object() && l["health"] == "ok";
}

TEST(LiftsLockstep, AMissionFromL1ToAPlaceOnL2RidesTheLiftAndArrives) {
  TwoFloors building;
  LockstepRobot robot(building.config());
  ASSERT_TRUE(robot.StepUntil([&] { return Localized(robot); }, 15.0)) << "never localized on L1";
  const LockstepRobot::Reply started = robot.Call(
      "POST", "/api/v1/missions", {{"waypoints", {{{"x", -1.0}, {"y", 0.5}, {"yaw", 3.14}, {"floor", "L2"}}}}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  std::vector<std::string> actions;
  for (const json& w : started.body["waypoints"]) actions.push_back(w["action"].get<std::string>());
  EXPECT_EQ(actions, (std::vector<std::string>{"ride_lift", "go"}));
  std::set<std::string> phases;
  const json done = UntilOver(robot, started.body["id"].get<std::string>(), 180.0, phases);
  ASSERT_EQ(Status(done), "succeeded") << done.dump();
  for (const char* phase : {"calling", "boarding", "riding", "leaving"}) {
    EXPECT_TRUE(phases.contains(phase)) << phase << " not among " << json(phases).dump();
  }
  ExpectOnL2At(robot, -1.0, 0.5);
  EXPECT_EQ(robot.Call("GET", "/api/v1/sim/lifts/lift1").body,
            (json{{"id", "lift1"}, {"floor", "L2"}, {"destination", ""}, {"door", "closed"}}))
      << "released: its door closed behind the robot";
}

TEST(LiftsLockstep, CancelledWhileRidingTheRobotGetsOutOnTheFloorItAskedFor) {
  TwoFloors building;
  LockstepRobot robot(building.config());
  ASSERT_TRUE(robot.StepUntil([&] { return Localized(robot); }, 15.0)) << "never localized on L1";
  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/missions", {{"waypoints", {{{"x", -1.0}, {"y", 0.5}, {"floor", "L2"}}}}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  const std::string id = started.body["id"].get<std::string>();
  ASSERT_TRUE(
      robot.StepUntil([&] { return robot.Call("GET", "/api/v1/missions/" + id).body["lift"] == "riding"; }, 90.0))
      << "never riding";
  const LockstepRobot::Reply cancelled = robot.Call("POST", "/api/v1/missions/" + id + "/cancel");
  EXPECT_LT(cancelled.status, 300) << cancelled.body.dump();
  // Out of the car on L2 at its lobby, the lift released (its door closed behind the robot), and free for the next
  // mission.
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        const json state = robot.State();
        return state["floor"] == "L2" && robot.Call("GET", "/api/v1/sim/lifts/lift1").body["door"] == "closed";
      },
      60.0))
      << "never out on L2 with the lift released";
  const json lobby = robot.State()["sim_true_pose"];
  EXPECT_LT(std::hypot(lobby["x"].get<double>() - 2.1, lobby["y"].get<double>() - 1.0), 0.3) << lobby.dump();
  EXPECT_EQ(Status(robot.Call("GET", "/api/v1/missions/" + id).body), "canceled");
  EXPECT_EQ(robot.Call("POST", "/api/v1/missions", {{"waypoints", {{{"x", 1.0}, {"y", 1.0}}}}}).status, 201);
}

}  // namespace
}  // namespace corridor
