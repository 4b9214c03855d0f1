#include "nav/mission/mission_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace corridor::nav {
namespace {

// An empty 10 x 10 m room at 5 cm.
std::shared_ptr<const Costmap> OpenRoom(const std::vector<Zone>& zones = {}) {
  return std::make_shared<const Costmap>(OccupancyGrid(200, 200, 0.05, Pose2{}, kFreeCell), zones, CostmapOptions{});
}

std::vector<LaneResult> FreeLanes() {
  std::vector<LaneResult> lanes;
  for (const double offset : {-0.15, -0.05, 0.05, 0.15}) {
    LaneResult lane;
    lane.offset_m = offset;
    lane.free_distance_m = 4.0;
    lanes.push_back(lane);
  }
  return lanes;
}

Mission ToGoal(const std::string& id, double x, double y) {
  MissionGoal goal;
  goal.pose = {x, y, 0.0};
  return Mission(id, {goal}, std::numeric_limits<double>::infinity());
}

// Drives a runner as the mission node does: a tick every 50 ms, a frame every 55 ms with free lanes, plans answered on
// `costmap` at once, the robot's pose integrated from the commands.
class Drive {
 public:
  explicit Drive(MissionRunner& runner, std::shared_ptr<const Costmap> costmap, Pose2 start)
      : runner_(runner), costmap_(std::move(costmap)), pose_(start) {}

  // Runs for `seconds`, or until the mission is over; returns whether it is over.
  bool For(double seconds, std::uint64_t version = 1, bool has_traffic = false) {
    for (const double end = now_ + seconds; now_ < end;) {
      now_ += 0.005;
      if (now_ >= next_tick_) {
        next_tick_ += 0.05;
        if (Handle(runner_.Tick(now_, pose_, version, has_traffic))) return true;
      }
      if (frames_ && now_ >= next_frame_) {
        next_frame_ += 0.055;
        FrameInput in;
        in.now_s = now_;
        in.pose = pose_;
        in.view.lanes = &lanes_;
        in.view.scan = &scan_;
        in.doors = &doors_;
        in.odom = odom_;
        in.lifts = &lifts_;
        if (Handle(runner_.Frame(in))) return true;
      }
      const Pose2 step{twist_.linear_mps * 0.005, 0.0, twist_.angular_rps * 0.005};
      pose_ = pose_ * step;
      odom_ = odom_ * step;
    }
    return false;
  }

  // Carries out what an update asks; true when the mission is over.
  bool Handle(const MissionUpdate& u) {
    if (u.command) twist_ = *u.command;
    requests_.insert(requests_.end(), u.doors.begin(), u.doors.end());
    lift_requests_.insert(lift_requests_.end(), u.lifts.begin(), u.lifts.end());
    if (u.switch_floor) {
      switched_ = u.switch_floor;
      pose_ = u.switch_floor->second;  // the new floor's map frame; odometry goes on
    }
    persisted_ += u.persist ? 1 : 0;
    if (u.check) {
      const bool free = RestOfPathTraversable(*costmap_, u.check->path, u.check->from);
      Handle(runner_.OnCheck(*u.check, free, costmap_, version_));
    }
    if (u.plan) {
      ++plans_;
      PathOptions options;
      const std::vector<float> extra =
          ExtraCosts(*costmap_, traffic_, u.plan->blocking, u.plan->blocking_radius_m, u.plan->blocking_cost);
      options.extra_cost = extra;
      options.robot_at_start = true;
      const PlanResult result = PlanPath(*costmap_, u.plan->start, u.plan->goal, u.plan->goal_yaw, nullptr, options);
      if (Handle(runner_.OnPlan(*u.plan, result, costmap_, version_, now_))) return true;
    }
    if (u.over) twist_ = {};
    return u.over;
  }

  MissionRunner& runner_;
  std::shared_ptr<const Costmap> costmap_;
  std::uint64_t version_ = 1;
  std::vector<float> traffic_;
  Pose2 pose_;
  Pose2 odom_ = pose_;  // the odometry frame: the start's map frame, exact
  Twist2 twist_;
  bool frames_ = true;
  std::vector<LaneResult> lanes_ = FreeLanes();
  double now_ = 0.0;
  double next_tick_ = 0.05;
  double next_frame_ = 0.055;
  int persisted_ = 0;
  int plans_ = 0;
  DoorReports doors_;
  std::vector<DoorRequest> requests_;
  std::vector<Eigen::Vector2d> scan_;  // the depth scan: nothing seen
  LiftReports lifts_;
  std::vector<LiftRequest> lift_requests_;
  std::optional<std::pair<std::string, Pose2>> switched_;
};

TEST(MissionRunnerTest, PlansItsLegAndDrivesItToTheGoal) {
  MissionRunner runner(MissionRunnerOptions{});
  EXPECT_TRUE(runner.Start(ToGoal("m1", 6.0, 5.0)).persist);
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  ASSERT_TRUE(drive.For(60.0));
  const MissionSnapshot s = runner.Snapshot();
  EXPECT_EQ(s.status, MissionStatus::kSucceeded);
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(6.0, 5.0)).norm(), 0.02);
  EXPECT_EQ(drive.plans_, 1);
  EXPECT_DOUBLE_EQ(s.progress, 1.0);
}

TEST(MissionRunnerTest, ExtendedWhileUnderWayItDrivesOnAndAGoalsSpeedLimitHoldsOnItsLeg) {
  MissionRunner runner(MissionRunnerOptions{});
  MissionGoal first;
  first.pose = {4.0, 5.0, 0.0};
  first.max_speed_mps = 0.2;
  runner.Start(Mission("m1", {first}, std::numeric_limits<double>::infinity()));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  double fastest = 0.0;
  for (int i = 0; i < 40; ++i) {
    drive.For(0.1);
    fastest = std::max(fastest, drive.twist_.linear_mps);
  }
  EXPECT_LE(fastest, 0.2 + 1e-9);
  EXPECT_GT(fastest, 0.15);
  MissionGoal second;
  second.pose = {7.0, 5.0, 0.0};
  MissionUpdate update;
  EXPECT_EQ(runner.Extend("m1", {second}, &update), TransitionOutcome::kOk);
  EXPECT_TRUE(update.persist);
  EXPECT_EQ(runner.Extend("other", {second}, &update), TransitionOutcome::kNotFound);
  ASSERT_TRUE(drive.For(60.0));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kSucceeded);
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(7.0, 5.0)).norm(), 0.02);
  EXPECT_EQ(runner.Extend("m1", {second}, &update), TransitionOutcome::kConflict);  // finished
}

TEST(MissionRunnerTest, ADoorOnThePathIsAskedForWaitedForAndReleasedOncePassed) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.SetDoors({{"d1", {5.0, 4.0}, {5.0, 6.0}}});
  runner.Start(ToGoal("m1", 8.0, 5.0));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  ASSERT_FALSE(drive.For(15.0));
  // Asked for once; held short of its line while it is closed.
  ASSERT_EQ(drive.requests_.size(), 1u);
  EXPECT_TRUE(drive.requests_[0].open);
  EXPECT_LT(drive.pose_.x_m, 5.0 - 1.4);  // hold_m (1.6) short of it, less the braking
  EXPECT_GT(drive.pose_.x_m, 3.0);
  EXPECT_EQ(runner.Snapshot().waiting_for_door, "d1");
  EXPECT_EQ(runner.Snapshot().policy, PolicyMode::kWaitingForDoor);
  drive.doors_["d1"] = {DoorStatus::kOpen, ""};
  ASSERT_TRUE(drive.For(30.0));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kSucceeded);
  ASSERT_EQ(drive.requests_.size(), 2u);
  EXPECT_EQ(drive.requests_[1].door, "d1");
  EXPECT_FALSE(drive.requests_[1].open);
}

TEST(MissionRunnerTest, ADoorThatRefusesEndsTheMissionBeforeTheRobotReachesIt) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.SetDoors({{"d1", {5.0, 4.0}, {5.0, 6.0}}});
  runner.Start(ToGoal("m1", 8.0, 5.0));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  drive.doors_["d1"] = {DoorStatus::kRefused, "locked for the night"};
  ASSERT_TRUE(drive.For(30.0));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kFailed);
  EXPECT_EQ(runner.Snapshot().error, "door d1 refused to open: locked for the night");
  EXPECT_LT(drive.pose_.x_m, 3.5);
  // What was asked for is released as the mission ends.
  ASSERT_EQ(drive.requests_.size(), 2u);
  EXPECT_FALSE(drive.requests_[1].open);
}

TEST(MissionRunnerTest, LostLocalizationPausesTheMissionUntilTheRobotIsFoundAgain) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 6.0, 5.0));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  ASSERT_FALSE(drive.For(2.0));
  const MissionUpdate lost = runner.SetLocalized(false);
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kPaused);
  EXPECT_TRUE(lost.persist || lost.publish);
  // Lost again and again while paused changes nothing; found, it drives on to the goal.
  runner.SetLocalized(false);
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kPaused);
  drive.Handle(runner.SetLocalized(true));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kActive);
  ASSERT_TRUE(drive.For(60.0));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kSucceeded);
}

TEST(MissionRunnerTest, AMissionPausedByAPersonIsNotResumedByLocalization) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 6.0, 5.0));
  MissionUpdate update;
  ASSERT_EQ(runner.Pause("m1", &update), TransitionOutcome::kOk);
  runner.SetLocalized(false);
  runner.SetLocalized(true);
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kPaused);
}

TEST(MissionRunnerTest, NoWayFailsTheMissionWithThePlannersReason) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 6.0, 5.0));
  // A keep-out zone round the goal.
  const Zone fence{"z", "fence", ZoneKind::kKeepOut, {{5.0, 4.0}, {7.0, 4.0}, {7.0, 6.0}, {5.0, 6.0}}};
  Drive drive(runner, OpenRoom({fence}), {2.0, 5.0, 0.0});
  ASSERT_TRUE(drive.For(1.0));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kFailed);
  EXPECT_FALSE(runner.Snapshot().error.empty());
  EXPECT_EQ(drive.twist_.linear_mps, 0.0);
}

TEST(MissionRunnerTest, WithoutDepthFramesItHoldsStillAndSaysSo) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 6.0, 5.0));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  drive.frames_ = false;
  EXPECT_FALSE(drive.For(2.0));
  EXPECT_EQ(runner.Snapshot().policy, PolicyMode::kWaitingForDepth);
  EXPECT_NEAR(drive.pose_.x_m, 2.0, 1e-9);
  drive.frames_ = true;
  drive.next_frame_ = drive.now_;
  EXPECT_FALSE(drive.For(1.0));
  EXPECT_EQ(runner.Snapshot().policy, PolicyMode::kFollow);
  EXPECT_GT(drive.pose_.x_m, 2.05);
}

TEST(MissionRunnerTest, AWallDrawnAcrossThePathMakesItPlanAgainAroundIt) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 8.0, 5.0));
  Drive drive(runner, OpenRoom(), {1.0, 5.0, 0.0});
  ASSERT_FALSE(drive.For(1.0));
  ASSERT_EQ(drive.plans_, 1);
  // A wall across the way at x = 5 m from y = 3 to 7 m: the map's version changes.
  OccupancyGrid walled(200, 200, 0.05, Pose2{}, kFreeCell);
  for (int y = 60; y < 140; ++y) walled.at({100, y}) = kOccupiedCell;
  drive.costmap_ = std::make_shared<const Costmap>(walled, std::vector<Zone>{}, CostmapOptions{});
  drive.version_ = 2;
  ASSERT_TRUE(drive.For(90.0, 2));
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kSucceeded);
  EXPECT_EQ(drive.plans_, 2);
}

TEST(MissionRunnerTest, WherePeopleWalkItTakesAPathThatGoesAnotherWayAndKeepsOneThatDoesNot) {
  MissionRunnerOptions options;
  options.navigator.reroute_s = 1.0;
  MissionRunner runner(options);
  runner.Start(ToGoal("m1", 8.0, 5.0));
  Drive drive(runner, OpenRoom(), {1.0, 5.0, 0.0});
  ASSERT_FALSE(drive.For(0.5));
  const auto farthest_off_the_line = [&] {
    double farthest = 0.0;
    for (const Pose2& p : runner.Snapshot().path) farthest = std::max(farthest, std::abs(p.y_m - 5.0));
    return farthest;
  };
  // Traffic everywhere alike: the reroutes find the same way, which is kept.
  drive.traffic_.assign(200 * 200, 1.0f);
  ASSERT_FALSE(drive.For(2.5, 1, true));
  EXPECT_GE(drive.plans_, 3);
  EXPECT_LT(farthest_off_the_line(), 0.05);
  // People walk across the middle of the room along y = 5: the next reroute goes round.
  for (int y = 90; y < 110; ++y) {
    for (int x = 0; x < 200; ++x) drive.traffic_[static_cast<std::size_t>(y * 200 + x)] = 0.0f;
  }
  for (int y = 80; y < 120; ++y) {
    for (int x = 90; x < 110; ++x) drive.traffic_[static_cast<std::size_t>(y * 200 + x)] = 50.0f;
  }
  ASSERT_FALSE(drive.For(1.5, 1, true));
  EXPECT_GT(farthest_off_the_line(), 0.5);
}

TEST(MissionRunnerTest, StartingAMissionCancelsTheOneInProgressAndStaleAnswersAreDropped) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.Start(ToGoal("m1", 6.0, 5.0));
  const MissionUpdate first = runner.Tick(0.1, Pose2{2.0, 5.0, 0.0}, 1, false);
  ASSERT_TRUE(first.plan);
  std::optional<MissionSnapshot> cancelled;
  runner.Start(ToGoal("m2", 3.0, 3.0), &cancelled);
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->id, "m1");
  EXPECT_EQ(cancelled->status, MissionStatus::kCanceled);
  // The answer to m1's query arrives after m2 started: it is not m2's path.
  const auto room = OpenRoom();
  const PlanResult m1_path = PlanPath(*room, first.plan->start, first.plan->goal);
  EXPECT_FALSE(runner.OnPlan(*first.plan, m1_path, room, 1, 0.2).persist);
  EXPECT_TRUE(runner.Snapshot().path.empty());
  MissionUpdate update;
  EXPECT_EQ(runner.Pause("m1", &update), TransitionOutcome::kNotFound);
  EXPECT_EQ(runner.Pause("m2", &update), TransitionOutcome::kOk);
  EXPECT_EQ(runner.Pause("m2", &update), TransitionOutcome::kConflict);
  EXPECT_EQ(runner.Cancel("m2", &update), TransitionOutcome::kOk);
  EXPECT_TRUE(update.over);
}

TEST(MissionRunnerTest, TheVoxelReactivePolicyDrivesTheSameMissionsOnObstaclePoints) {
  MissionRunnerOptions options;
  options.policy = LocalPolicyKind::kVoxelReactive;
  MissionRunner runner(options);
  runner.Start(ToGoal("m1", 6.0, 5.0));
  Drive drive(runner, OpenRoom(), {2.0, 5.0, 0.0});
  drive.For(2.0);
  EXPECT_EQ(runner.Snapshot().policy, PolicyMode::kReactive);
  drive.For(20.0);
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(6.0, 5.0)).norm(), 0.3);
}

// A lift with its door at x = 2 (y 0..1) on L1, lobby (1, 0.5) facing it; on L2 at y = 3 (x 5..6), lobby (5.5, 2).
Building OneLift() {
  Building b;
  b.floors = {{"L1", "ground"}, {"L2", "first"}};
  Lift lift;
  lift.id = "east";
  lift.stops = {{"L1", {"east@L1", {2.0, 0.0}, {2.0, 1.0}}, {1.0, 0.5, 0.0}},
                {"L2", {"east@L2", {5.0, 3.0}, {6.0, 3.0}}, {5.5, 2.0, M_PI / 2}}};
  b.lifts = {lift};
  return b;
}

Mission RideFromL1ToL2(const std::string& id) {
  MissionGoal ride;
  ride.pose = {1.0, 0.5, 0.0};
  ride.has_yaw = true;
  ride.action = GoalAction::kRideLift;
  ride.lift = "east";
  ride.floor = "L1";
  ride.ride_to = "L2";
  return Mission(id, {ride}, std::numeric_limits<double>::infinity());
}

LiftReport OpenAt(const std::string& floor) {
  LiftReport r;
  r.floor = floor;
  r.door_open = true;
  return r;
}

// Cancelled while the car travels, the robot is not left in it with the old floor's map: the ride goes on to the floor
// asked for, the map is switched there, the robot leaves to the lobby, and only then is the lift released.
TEST(MissionRunnerTest, ACancelWhileTheCarTravelsEndsOutOfTheCarOnTheFloorItArrivesAt) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.SetBuilding(OneLift());
  runner.Start(RideFromL1ToL2("m1"));
  Drive drive(runner, OpenRoom(), {1.0, 0.5, 0.0});
  drive.lifts_["east"] = OpenAt("L1");
  for (int i = 0; i < 600 && runner.Snapshot().lift != "riding"; ++i) drive.For(0.05);
  ASSERT_EQ(runner.Snapshot().lift, "riding");
  drive.lifts_["east"].door_open = false;
  drive.lifts_["east"].moving = true;
  drive.For(1.0);
  MissionUpdate cancel;
  ASSERT_EQ(runner.Cancel("m1", &cancel), TransitionOutcome::kOk);
  drive.Handle(cancel);
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kCanceled);
  EXPECT_TRUE(runner.leaving_lift());
  EXPECT_FALSE(runner.MayLookAround());
  const auto released = [&] {
    return std::any_of(drive.lift_requests_.begin(), drive.lift_requests_.end(),
                       [](const LiftRequest& r) { return r.release; });
  };
  EXPECT_FALSE(released()) << "the lift was let go with the robot in its car";
  drive.For(2.0);
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(2.7, 0.5)).norm(), 0.06) << "it moved in the car";
  drive.lifts_["east"] = OpenAt("L2");
  for (int i = 0; i < 600 && runner.leaving_lift(); ++i) drive.For(0.05);
  EXPECT_FALSE(runner.leaving_lift());
  ASSERT_TRUE(drive.switched_) << "no switch to the floor it arrived at";
  EXPECT_EQ(drive.switched_->first, "L2");
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(5.5, 2.0)).norm(), 0.06) << "not out at the lobby on L2";
  EXPECT_TRUE(released());
  EXPECT_EQ(runner.Snapshot().status, MissionStatus::kCanceled);
}

// Cancelled on the way into the car, it backs out to the lobby it came from, on the same floor, then lets the lift go.
TEST(MissionRunnerTest, ACancelWhileBoardingBacksOutToTheLobby) {
  MissionRunner runner(MissionRunnerOptions{});
  runner.SetBuilding(OneLift());
  runner.Start(RideFromL1ToL2("m1"));
  Drive drive(runner, OpenRoom(), {1.0, 0.5, 0.0});
  drive.lifts_["east"] = OpenAt("L1");
  for (int i = 0; i < 600 && drive.pose_.x_m < 1.8; ++i) drive.For(0.05);
  ASSERT_EQ(runner.Snapshot().lift, "boarding");
  MissionUpdate cancel;
  ASSERT_EQ(runner.Cancel("m1", &cancel), TransitionOutcome::kOk);
  drive.Handle(cancel);
  for (int i = 0; i < 600 && runner.leaving_lift(); ++i) drive.For(0.05);
  EXPECT_FALSE(runner.leaving_lift());
  EXPECT_FALSE(drive.switched_);
  EXPECT_LT((drive.pose_.translation() - Eigen::Vector2d(1.0, 0.5)).norm(), 0.06) << "not back at the lobby";
  ASSERT_FALSE(drive.lift_requests_.empty());
  EXPECT_TRUE(drive.lift_requests_.back().release);
  for (const LiftRequest& r : drive.lift_requests_) EXPECT_NE(r.floor, "L2") << "it asked for the other floor";
}

}  // namespace
}  // namespace corridor::nav
