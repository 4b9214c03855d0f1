// Missions through the daemon's graph in simulated time (testing/lockstep_robot.h), in a small real arena
// (lse_arena, 4 x 3 m): a lower room and two upper rooms joined by one 1.2 m doorway (x 0.8 to 2.0, y about 1.5).
// Odometry is noiseless here so that accuracy is the controller's. A goal is reached within 2 cm and 2 degrees; a
// paused mission stands still and resumes; a named place is a goal, and one the robot cannot stand at is refused; a
// keep-out zone across the doorway refuses the way, and drawn during a mission stops it before the zone. (The requests'
// transport, their validation against the OpenAPI document and what survives a restart are
// tests/navigation_test.mjs.)
#include <gtest/gtest.h>

#include <map>

#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>

#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"
#include "testing/temp_dir.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;

const json kUpperRoom = {{"x", 1.0}, {"y", 2.4}};
const json kDoorway = json::array({{0.7, 1.2}, {2.1, 1.2}, {2.1, 1.8}, {0.7, 1.8}});

class MissionsLockstep : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_.path() / "corridor.yaml")
        << "devices: {laser: {driver: none}}\n"
           "sim:\n"
           "  world: \""
        << (testing::SourceDir() / "tests/data/maps/lse_arena/lse_arena.yaml").string()
        << "\"\n"
           "  start: {x_m: 1.0, y_m: 0.75, yaw_deg: 0}\n"
           "  camera: {rate_hz: 15, width: 160, height: 120}\n"
           "  base: {odom_linear_noise: 0, odom_angular_noise: 0}\n";
    robot_ = std::make_unique<LockstepRobot>(dir_.path() / "corridor.yaml");
  }

  // Starts a mission; its id.
  std::string Start(const json& body) {
    const LockstepRobot::Reply started = robot_->Call("POST", "/api/v1/missions", body);
    EXPECT_EQ(started.status, 201) << started.body.dump();
    return started.body.value("id", "");
  }
  json Mission(const std::string& id) { return robot_->Call("GET", "/api/v1/missions/" + id).body; }
  // Steps until mission `id` is no longer active (at most max_s of simulated time); the mission then.
  json UntilOver(const std::string& id, double max_s) {
    json mission;
    robot_->StepUntil(
        [&] {
          mission = Mission(id);
          return mission["status"] != "active";
        },
        max_s);
    return mission;
  }
  bool UntilMoving(double max_s) {
    return robot_->StepUntil([&] { return robot_->State()["velocity"]["linear_mps"].get<double>() > 0.1; }, max_s);
  }
  Eigen::Vector2d Truth() {
    const json t = robot_->State()["sim_true_pose"];
    return {t["x"].get<double>(), t["y"].get<double>()};
  }

  testing::TempDir dir_{"corridor_arena"};
  std::unique_ptr<LockstepRobot> robot_;
};

TEST_F(MissionsLockstep, AGoalIsReachedWithinTwoCentimetresAndTwoDegrees) {
  const double yaw = std::numbers::pi / 2;
  const std::string id = Start({{"waypoints", json::array({{{"x", 3.0}, {"y", 0.9}, {"yaw", yaw}}})}});
  json running;
  ASSERT_TRUE(robot_->StepUntil(
      [&] {
        running = Mission(id);
        return running["path"].size() >= 2;
      },
      5.0));
  EXPECT_EQ(running["status"], "active");
  EXPECT_GT(running["eta_s"].get<double>(), 0.0);
  const json done = UntilOver(id, 30.0);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(done["progress"], 1);
  robot_->StepFor(0.1);  // the state of the next tick: idle as soon as the mission ends
  const json s = robot_->State();
  const json& t = s["sim_true_pose"];
  EXPECT_LE(std::hypot(t["x"].get<double>() - 3.0, t["y"].get<double>() - 0.9) * 100.0, 2.0) << t.dump();
  EXPECT_LE(std::abs(std::remainder(t["yaw"].get<double>() - yaw, 2 * std::numbers::pi)) * 180 / std::numbers::pi, 2.0)
      << t.dump();
  EXPECT_EQ(s["mode"], "idle");
  bool listed = false;
  const json missions = robot_->Call("GET", "/api/v1/missions").body["missions"];
  for (const json& m : missions) {
    listed = listed || (m["id"] == id && m["status"] == "succeeded");
  }
  EXPECT_TRUE(listed) << "not kept";
}

TEST_F(MissionsLockstep, AMissionReplacedByAnotherIsKeptAsCanceled) {
  const std::string first = Start({{"waypoints", json::array({{{"x", 3.0}, {"y", 0.75}}})}});
  const std::string second = Start({{"waypoints", json::array({{{"x", 2.0}, {"y", 0.75}}})}});
  robot_->StepFor(0.2);
  const json missions = robot_->Call("GET", "/api/v1/missions").body["missions"];
  std::map<std::string, std::string> kept;
  for (const json& m : missions) {
    kept[m["id"].get<std::string>()] = m["status"].get<std::string>();
  }
  EXPECT_EQ(kept[first], "canceled");
  EXPECT_EQ(kept[second], "active");
}

TEST_F(MissionsLockstep, APausedMissionStaysStillResumesAndFinishes) {
  const std::string id = Start({{"waypoints", json::array({{{"x", 3.0}, {"y", 0.75}}})}, {"speed_limit_mps", 0.3}});
  ASSERT_TRUE(UntilMoving(8.0)) << "the robot never drove";
  const LockstepRobot::Reply paused = robot_->Call("POST", "/api/v1/missions/" + id + "/pause", json::object());
  ASSERT_EQ(paused.status, 200) << paused.body.dump();
  EXPECT_EQ(paused.body["status"], "paused");
  EXPECT_EQ(robot_->Call("POST", "/api/v1/missions/" + id + "/pause", json::object()).status, 409);
  robot_->StepFor(0.8);  // braking
  const Eigen::Vector2d held = Truth();
  robot_->StepFor(1.5);
  EXPECT_LT((Truth() - held).norm(), 0.002) << "it moved while paused";
  EXPECT_EQ(robot_->Call("POST", "/api/v1/missions/" + id + "/resume", json::object()).body["status"], "active");
  const json done = UntilOver(id, 30.0);
  EXPECT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(robot_->Call("POST", "/api/v1/missions/" + id + "/cancel", json::object()).status, 409);
  EXPECT_EQ(robot_->Call("POST", "/api/v1/missions/nope/cancel", json::object()).status, 404);
}

// The console's emergency stop: one request stops the robot and pauses its mission, which resumes where it was.
TEST_F(MissionsLockstep, StopHaltsTheRobotAndPausesItsMissionWhichThenResumes) {
  const LockstepRobot::Reply idle = robot_->Call("POST", "/api/v1/stop", json::object());
  ASSERT_EQ(idle.status, 200) << idle.body.dump();
  EXPECT_TRUE(idle.body["paused"].is_null()) << "no mission to pause";
  const std::string id = Start({{"waypoints", json::array({{{"x", 3.0}, {"y", 0.75}}})}, {"speed_limit_mps", 0.3}});
  ASSERT_TRUE(UntilMoving(8.0)) << "the robot never drove";
  const LockstepRobot::Reply stopped = robot_->Call("POST", "/api/v1/stop", json::object());
  ASSERT_EQ(stopped.status, 200) << stopped.body.dump();
  EXPECT_EQ(stopped.body["paused"]["id"], id);
  EXPECT_EQ(stopped.body["paused"]["status"], "paused");
  robot_->StepFor(0.8);  // braking
  const Eigen::Vector2d held = Truth();
  robot_->StepFor(1.5);
  EXPECT_LT((Truth() - held).norm(), 0.002) << "it moved after the stop";
  EXPECT_EQ(robot_->Call("POST", "/api/v1/missions/" + id + "/resume", json::object()).body["status"], "active");
  EXPECT_EQ(UntilOver(id, 30.0)["status"], "succeeded");
}

TEST_F(MissionsLockstep, ANamedPlaceIsAGoalAndOneTheRobotCannotStandAtIsRefused) {
  ASSERT_EQ(robot_->Call("POST", "/api/v1/places", {{"name", "desk"}, {"x", 2.5}, {"y", 0.7}, {"yaw", 0}}).status, 201);
  EXPECT_EQ(robot_->Call("POST", "/api/v1/places", {{"name", "desk"}, {"x", 1}, {"y", 1}}).status, 409);
  // On the wall between the rooms, off the map: refused, saying why, and not kept.
  const LockstepRobot::Reply wall =
      robot_->Call("POST", "/api/v1/places", {{"name", "nowhere"}, {"x", 3.0}, {"y", 1.5}});
  EXPECT_EQ(wall.status, 422) << wall.body.dump();
  const LockstepRobot::Reply off =
      robot_->Call("POST", "/api/v1/places", {{"name", "nowhere"}, {"x", 100}, {"y", 100}});
  EXPECT_EQ(off.status, 422) << off.body.dump();
  EXPECT_NE(off.body.value("detail", "").find("outside the map"), std::string::npos) << off.body.dump();
  const json places = robot_->Call("GET", "/api/v1/places").body["places"];
  for (const json& p : places) EXPECT_NE(p["name"], "nowhere");
  const std::string id = Start({{"waypoints", json::array({{{"place", "desk"}}})}});
  const json done = UntilOver(id, 30.0);
  EXPECT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(done["waypoints"][0]["place"], "desk");
}

TEST_F(MissionsLockstep, AKeepOutZoneAcrossTheOnlyDoorwayRefusesTheWayAndNothingMoves) {
  const LockstepRobot::Reply zone =
      robot_->Call("POST", "/api/v1/zones", {{"name", "wet floor"}, {"kind", "keep_out"}, {"polygon", kDoorway}});
  ASSERT_EQ(zone.status, 201) << zone.body.dump();
  const LockstepRobot::Reply plan = robot_->Call("POST", "/api/v1/plan", {{"goal", kUpperRoom}});
  EXPECT_EQ(plan.status, 422);
  EXPECT_EQ(plan.body["code"], "no_path");
  const Eigen::Vector2d before = Truth();
  const json failed = UntilOver(Start({{"waypoints", json::array({kUpperRoom})}}), 5.0);
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_NE(failed.value("error", "").find("no path"), std::string::npos) << failed.dump();
  robot_->StepFor(0.5);
  EXPECT_LT((Truth() - before).norm(), 0.005) << "it moved";
  // A goal inside the zone is refused up front.
  const LockstepRobot::Reply inside =
      robot_->Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", 1.4}, {"y", 1.5}}})}});
  EXPECT_EQ(inside.status, 422);
  EXPECT_NE(inside.body.value("detail", "").find("keep-out"), std::string::npos) << inside.body.dump();
  ASSERT_EQ(robot_->Call("DELETE", "/api/v1/zones/" + zone.body["id"].get<std::string>()).status, 204);
  EXPECT_EQ(robot_->Call("POST", "/api/v1/plan", {{"goal", kUpperRoom}}).status, 200);
}

TEST_F(MissionsLockstep, AZoneDrawnAcrossThePathDuringAMissionIsRespectedAtOnce) {
  const std::string id = Start({{"waypoints", json::array({kUpperRoom})}, {"speed_limit_mps", 0.25}});
  ASSERT_TRUE(UntilMoving(8.0)) << "the robot never drove";
  ASSERT_EQ(
      robot_->Call("POST", "/api/v1/zones", {{"name", "closed"}, {"kind", "keep_out"}, {"polygon", kDoorway}}).status,
      201);
  EXPECT_EQ(UntilOver(id, 8.0)["status"], "failed");
  robot_->StepFor(1.0);
  const json s = robot_->State();
  EXPECT_LT(s["sim_true_pose"]["y"].get<double>(), 1.2) << "it went into the zone";
  EXPECT_EQ(s["velocity"]["linear_mps"], 0.0);
}

}  // namespace
}  // namespace corridor
