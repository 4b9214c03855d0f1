// Navigation behaviour of the daemon's graph in simulated time (testing/lockstep_robot.h), in the shipped default
// configuration (Willow Garage, the laser, Monte Carlo localization): what a user of the robot would notice, checked
// against the simulator's truth at the same simulated instant, so that no machine's load can decide the outcome.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "drivers/sim/world.h"
#include "nav/map/map_io.h"
#include "nav/planner/planner.h"
#include "server/runtime/topics.h"
#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
using testing::ShippedConfig;

// The simulator's truth kept by stamp, to compare the robot's pose with the truth when that pose was made.
class Truth {
 public:
  explicit Truth(LockstepRobot& robot) : robot_(robot) {}
  // Records the newest truth; call once per step.
  void Record() {
    if (const auto truth = robot_.graph().bus().Get(server::topics::kSimTruePose).latest()) {
      by_stamp_[truth->stamp_ns] = truth->pose;
      while (by_stamp_.size() > 1000) by_stamp_.erase(by_stamp_.begin());
    }
  }
  // The robot's newest pose against the truth at its stamp: metres and degrees, or nothing yet.
  std::optional<std::pair<double, double>> Error() const {
    const auto pose = robot_.graph().bus().Get(server::topics::kPose).latest();
    if (!pose || by_stamp_.empty()) return std::nullopt;
    auto at = by_stamp_.lower_bound(pose->stamp_ns);
    if (at == by_stamp_.end()) at = std::prev(at);
    const nav::Pose2& truth = at->second;
    return std::make_pair((pose->pose.translation() - truth.translation()).norm(),
                          std::abs(nav::WrapAngle(pose->pose.yaw_rad - truth.yaw_rad)) * 180.0 / M_PI);
  }

 private:
  LockstepRobot& robot_;
  std::map<drivers::TimeNs, nav::Pose2> by_stamp_;
};

std::string Health(LockstepRobot& robot) {
  const auto state = robot.graph().bus().Get(server::topics::kLocalization).latest();
  return state ? nav::ToString(state->estimate.health) : "";
}

std::string StatusOf(LockstepRobot& robot) {
  const auto mission = robot.graph().bus().Get(server::topics::kMission).latest();
  return mission ? nav::ToString(mission->status) : "";
}

// Runs a mission through `waypoints` in `robot` and returns the worst error of its pose against the truth at the pose's
// stamp (metres, degrees) and the mission's end status.
struct MissionRun {
  double worst_m = 0.0;
  double worst_deg = 0.0;
  std::string status;
};
MissionRun RunMission(LockstepRobot& robot, const json& waypoints, double max_s) {
  const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/missions", {{"waypoints", waypoints}});
  EXPECT_EQ(started.status, 201) << started.body.dump();
  Truth truth(robot);
  MissionRun run;
  robot.StepUntil(
      [&] {
        truth.Record();
        if (const auto error = truth.Error()) {
          run.worst_m = std::max(run.worst_m, error->first);
          run.worst_deg = std::max(run.worst_deg, error->second);
        }
        return StatusOf(robot) != "active";
      },
      max_s);
  run.status = StatusOf(robot);
  std::printf("worst error during the mission: %.1f cm, %.2f deg\n", 100.0 * run.worst_m, run.worst_deg);
  return run;
}

// Localization follows a mission within centimetres of the truth (Wang et al. report about 1 cm; the benchmark measures
// 0.8 cm RMSE over 241 m). Issue 36: in a real-time daemon this check depended on the machine's load, because the
// error was measured between a pose and a truth read at different moments.
TEST(NavigationLockstep, LocalizationFollowsAMissionWithinCentimetresOfTheTruth) {
  LockstepRobot robot(ShippedConfig());
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  const MissionRun run = RunMission(
      robot, json::array({{{"x", 24.4}, {"y", 26.5}}, {{"x", 25.0}, {"y", 27.2}}, {{"x", 24.4}, {"y", 24.6}}}), 120.0);
  EXPECT_EQ(run.status, "succeeded");
  EXPECT_LT(run.worst_m, 0.05);
  EXPECT_LT(run.worst_deg, 3.0);
}

// The same from the depth camera's scans alone (no laser): within 10 cm and 4 degrees.
TEST(NavigationLockstep, LocalizationFromTheDepthCameraFollowsAMission) {
  LockstepRobot robot(ShippedConfig(), [](server::Config& c) { c.devices.laser.driver = server::DeviceDriver::kNone; });
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  const MissionRun run = RunMission(robot, json::array({{{"x", 24.4}, {"y", 26.5}}, {{"x", 25.0}, {"y", 27.2}}}), 90.0);
  EXPECT_EQ(run.status, "succeeded");
  EXPECT_LT(run.worst_m, 0.1);
  EXPECT_LT(run.worst_deg, 4.0);
}

// A robot with a laser and no camera (a TurtleBot 3 Burger): its laser's lanes steer the mission, as a camera's would,
// down the corridor west of the start, through the narrow passage north, and back. (Waypoints in the open: the laser
// sees walls right beside the robot that a camera, blind nearer than half a metre, does not, so a goal the map puts
// within the gate's margin of a wall is reached by the camera robot and missed by 0.15 m by the laser robot.)
TEST(NavigationLockstep, ARobotWithoutACameraRunsAMissionOnItsLasersLanes) {
  LockstepRobot robot(ShippedConfig(),
                      [](server::Config& c) { c.devices.camera.driver = server::DeviceDriver::kNone; });
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  const MissionRun run = RunMission(
      robot, json::array({{{"x", 22.5}, {"y", 24.3}}, {{"x", 20.7}, {"y", 25.5}}, {{"x", 24.0}, {"y", 24.3}}}), 120.0);
  EXPECT_EQ(run.status, "succeeded");
  EXPECT_LT(run.worst_m, 0.05);
  EXPECT_FALSE(robot.graph().bus().Get(server::topics::kBumped).latest());
}

// The same with a rotating laser, as an RPLIDAR measures (each beam as the laser comes round to it, over 0.1 s, while
// the robot turns at up to 1.5 rad/s at the waypoints): its sweeps undone by the odometry, it stays within 5 cm.
TEST(NavigationLockstep, ARobotWithARotatingLaserStaysLocalizedThroughItsTurns) {
  LockstepRobot robot(ShippedConfig(), [](server::Config& c) {
    c.devices.camera.driver = server::DeviceDriver::kNone;
    c.sim.robot.laser.sweep = true;
  });
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  const MissionRun run = RunMission(
      robot, json::array({{{"x", 22.5}, {"y", 24.3}}, {{"x", 20.7}, {"y", 25.5}}, {{"x", 24.0}, {"y", 24.3}}}), 120.0);
  EXPECT_EQ(run.status, "succeeded");
  EXPECT_LT(run.worst_m, 0.05);
  EXPECT_LT(run.worst_deg, 2.0);
}

// Issue 36: driven by hand beside a wall near the start, onto an island of free space among the map's unknown specks
// (cut off from the rest by their inflation), a mission to the other end of the corridor failed at once with "no path
// from (24, 25.5)", though the plan preview had found one; once it found a way out, it sat still, refused by the map's
// specks at every turn, for minutes; a two-waypoint mission from there failed at "waypoint 1 of 2" on replanning. The
// robot must leave the margin by itself (slowly) and go, through every waypoint.
TEST(NavigationLockstep, AMissionFromAnIslandAmongTheMapsSpecksFindsItsWayOutAndGoes) {
  const json goal = {{"x", 18.0}, {"y", 26.0}};
  for (const json& waypoints : {json::array({goal}), json::array({{{"x", 22.0}, {"y", 24.3}}, goal})}) {
    LockstepRobot robot(ShippedConfig(), [](server::Config& c) { c.sim.robot.start = {24.0, 25.5, 3.1}; });
    ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
    const LockstepRobot::Reply preview = robot.Call("POST", "/api/v1/plan", {{"goal", waypoints[0]}});
    ASSERT_EQ(preview.status, 200) << preview.body.dump();
    // Across the band at a crawl.
    bool crawls = false;
    for (const json& w : preview.body["path"]) {
      crawls |= w["speed_limit_mps"].is_number() && w["speed_limit_mps"].get<double>() <= nav::kBandSpeedMps + 1e-9;
    }
    EXPECT_TRUE(crawls) << preview.body["path"].dump();
    const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/missions", {{"waypoints", waypoints}});
    ASSERT_EQ(started.status, 201) << started.body.dump();
    robot.StepUntil([&] { return StatusOf(robot) != "active"; }, 120.0);
    const json mission = robot.State()["mission"];
    EXPECT_EQ(mission["status"], "succeeded") << waypoints.size() << " waypoints: " << mission.dump().substr(0, 600);
  }
}

// Willow Garage's map has specks and a band of unknown (grey) cells just north of the start; a goal beyond them is
// reached the planned way, a 13 m detour west, never through the band (MORP-RB used to swerve for the mapped specks,
// cross the band, free floor in the simulator, and then fail to plan from an "obstacle" cell). On from there to a goal
// 0.9 m away round a corner of the path beside the same specks, without the loop the follower used to drive when its
// arc cut the corner (2.9 m).
TEST(NavigationLockstep, AGoalBehindTheSpecksIsReachedTheLongWayRoundAndTheNextWithoutALoop) {
  LockstepRobot robot(ShippedConfig());
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  bool bumped = false;
  std::optional<nav::Pose2> in_band;
  double driven_m = 0.0;
  std::optional<nav::Pose2> last;
  const auto watch = [&] {
    bumped |= robot.sim().bumper_pressed();
    const nav::Pose2 p = robot.sim().true_pose();
    if (p.x_m > 22.8 && p.x_m < 25.2 && p.y_m > 25.9 && p.y_m < 26.2 && !in_band) in_band = p;
    if (last) driven_m += (p.translation() - last->translation()).norm();
    last = p;
    return StatusOf(robot) != "active";
  };
  ASSERT_EQ(robot.Call("POST", "/api/v1/missions", {{"waypoints", {{{"x", 24.4}, {"y", 26.5}}}}}).status, 201);
  robot.StepUntil(watch, 150.0);
  ASSERT_EQ(StatusOf(robot), "succeeded") << robot.State()["mission"].dump();
  EXPECT_FALSE(bumped) << "the robot touched something";
  EXPECT_FALSE(in_band.has_value()) << "the robot crossed the grey band at " << in_band->x_m << ", " << in_band->y_m;
  EXPECT_LT((robot.sim().true_pose().translation() - Eigen::Vector2d(24.4, 26.5)).norm(), 0.06);

  ASSERT_EQ(robot.Call("POST", "/api/v1/missions", {{"waypoints", {{{"x", 25.0}, {"y", 27.2}}}}}).status, 201);
  driven_m = 0.0;
  robot.StepUntil(watch, 60.0);
  ASSERT_EQ(StatusOf(robot), "succeeded") << robot.State()["mission"].dump();
  EXPECT_FALSE(bumped) << "the robot touched something";
  EXPECT_LT(driven_m, 1.6) << "for a 1.2 m path";
}

// A mission that cannot go on ends, saying why; while it tries, the state says what it waits for. A box the map does
// not show fills a room from wall to wall between the robot and its goal.
TEST(NavigationLockstep, AMissionThatCannotGoOnEndsWithTheReasonAndSaysWhatItWaitsFor) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("corridor_blocked_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  nav::SaveMap(drivers::sim::RoomMap(6.0, 3.0, 0.05), dir / "room.yaml");
  std::ofstream(dir / "corridor.yaml")
      << "sim:\n  world: room.yaml\n  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}\n"
         "  obstacles:\n    - {shape: box, x_m: 3.5, y_m: 1.5, size_m: 1.6, height_m: 1.0}\n"
         "localization: {source: sim_truth}\n"
         // the planner knows nothing of the box: only the camera sees it
         "octomap: {costmap_layer: false}\n";
  {
    LockstepRobot robot(dir / "corridor.yaml");
    robot.StepFor(1.0);
    const LockstepRobot::Reply started =
        robot.Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", 5.5}, {"y", 1.5}}})}});
    ASSERT_EQ(started.status, 201) << started.body.dump();
    std::string waited;
    robot.StepUntil(
        [&] {
          const auto mission = robot.graph().bus().Get(server::topics::kMission).latest();
          if (mission && !mission->waiting.empty()) waited = mission->waiting;
          return StatusOf(robot) != "active";
        },
        150.0);
    const json mission = robot.State()["mission"];
    EXPECT_EQ(mission["status"], "failed") << mission.dump().substr(0, 600);
    EXPECT_EQ(mission["error"].get<std::string>().rfind("no way forward", 0), 0u) << mission["error"];
    EXPECT_NE(waited.find("a way past what blocks it"), std::string::npos) << waited;
    EXPECT_EQ(mission["waiting"], "");
  }
  std::filesystem::remove_all(dir);
}

// Issue 36: "Set pose" said "pose set" and the estimate jumped back within 1.5 s. A pose near the truth, given while
// the robot stands still, settles there without it moving; a pose the scans contradict is taken, and the reply says so.
TEST(NavigationLockstep, APoseGivenStandingStillSettlesAndOneTheScansContradictIsSaidSo) {
  LockstepRobot robot(ShippedConfig());
  ASSERT_TRUE(robot.StepUntil([&] { return Health(robot) == "ok"; }, 10.0)) << "localization never ok";
  const nav::Pose2 truth = robot.graph().bus().Get(server::topics::kSimTruePose).latest()->pose;
  const json near = {{"x", truth.x_m + 0.15}, {"y", truth.y_m - 0.1}, {"yaw", truth.yaw_rad + 0.1}, {"sigma_m", 0.3}};
  const LockstepRobot::Reply taken = robot.Call("PUT", "/api/v1/localization/pose", near);
  ASSERT_EQ(taken.status, 202) << taken.body.dump();
  EXPECT_TRUE(taken.body["agrees"].get<bool>()) << taken.body.dump();
  // Standing still (no command at all), it settles on the truth.
  Truth at(robot);
  const bool settled = robot.StepUntil(
      [&] {
        at.Record();
        const auto error = at.Error();
        return Health(robot) == "ok" && error && error->first < 0.05 && error->second < 2.0;
      },
      5.0);
  EXPECT_TRUE(settled) << "health " << Health(robot);
  const auto moved = robot.graph().bus().Get(server::topics::kSimTruePose).latest()->pose;
  EXPECT_LT((moved.translation() - truth.translation()).norm(), 0.01) << "the robot moved";
  // Three metres off, where the walls are elsewhere: taken, and said not to fit.
  const json off = {{"x", truth.x_m}, {"y", truth.y_m + 3.0}, {"yaw", truth.yaw_rad + 1.5}};
  const LockstepRobot::Reply disputed = robot.Call("PUT", "/api/v1/localization/pose", off);
  ASSERT_EQ(disputed.status, 202) << disputed.body.dump();
  EXPECT_FALSE(disputed.body["agrees"].get<bool>()) << disputed.body.dump();
  EXPECT_LT(disputed.body["agreement"].get<double>(), disputed.body["agreement_before"].get<double>());
  EXPECT_NE(disputed.body["detail"].get<std::string>().find("does not fit"), std::string::npos);
}

}  // namespace
}  // namespace corridor
