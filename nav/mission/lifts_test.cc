#include "nav/mission/lifts.h"

#include <gtest/gtest.h>

#include <cmath>

namespace corridor::nav {
namespace {

// Two floors whose maps are turned a quarter turn to each other. On L1 the lift's door spans y 0..1 at x = 2 with the
// lobby at (1, 0.5) facing +x; on L2 it spans x 5..6 at y = 3 with the lobby at (5.5, 2) facing +y.
Building TurnedFloors() {
  Building b;
  b.floors = {{"L1", "ground"}, {"L2", "first"}, {"L3", "roof"}};
  Lift lift;
  lift.id = "east";
  lift.stops = {{"L1", {"east/L1", {2.0, 0.0}, {2.0, 1.0}}, {1.0, 0.5, 0.0}},
                {"L2", {"east/L2", {5.0, 3.0}, {6.0, 3.0}}, {5.5, 2.0, M_PI / 2}}};
  b.lifts = {lift};
  return b;
}

LiftReport At(const std::string& floor, bool door_open, bool moving = false) {
  LiftReport r;
  r.floor = floor;
  r.door_open = door_open;
  r.moving = moving;
  return r;
}

MissionGoal GoalOn(const std::string& floor, double x, double y) {
  MissionGoal g;
  g.pose = {x, y, 0.0};
  g.floor = floor;
  return g;
}

TEST(LiftsTest, AGoalOnAnotherFloorGoesThroughALiftServingBoth) {
  const Building b = TurnedFloors();
  EXPECT_NO_THROW(Validate(b));
  const auto goals = ThroughLifts(b, "L1", {GoalOn("", 0.5, 0.5), GoalOn("L2", 7.0, 7.0), GoalOn("", 8.0, 7.0)});
  ASSERT_EQ(goals.size(), 4u);
  EXPECT_EQ(goals[0].floor, "L1");
  EXPECT_EQ(goals[1].action, GoalAction::kRideLift);
  EXPECT_EQ(goals[1].lift, "east");
  EXPECT_EQ(goals[1].floor, "L1");
  EXPECT_EQ(goals[1].ride_to, "L2");
  EXPECT_NEAR(goals[1].pose.x_m, 1.0, 1e-12);  // the lobby on L1
  EXPECT_TRUE(goals[1].has_yaw);
  EXPECT_EQ(goals[2].floor, "L2");
  EXPECT_EQ(goals[3].floor, "L2");                                                   // after it, on the same floor
  EXPECT_THROW(ThroughLifts(b, "L1", {GoalOn("L3", 0, 0)}), std::invalid_argument);  // no lift goes there
  EXPECT_THROW(ThroughLifts(b, "L1", {GoalOn("L9", 0, 0)}), std::invalid_argument);
  Building twice = b;
  twice.floors.push_back({"L1", "other"});
  EXPECT_THROW(Validate(twice), std::invalid_argument);
  Building one_stop = b;
  one_stop.lifts[0].stops.pop_back();
  EXPECT_THROW(Validate(one_stop), std::invalid_argument);
}

TEST(LiftsTest, AStopDrawnOnAFloorJoinsItsLiftOrMakesOne) {
  Building b = TurnedFloors();
  PutStop(b, "west", {"L3", {"", {0.0, 0.0}, {1.0, 0.0}}, {0.5, -0.8, M_PI / 2}});
  ASSERT_EQ(b.lifts.size(), 2u);
  EXPECT_EQ(b.lifts[1].stops[0].door.id, "west@L3");
  EXPECT_EQ(b.lifts[1].car_width_m, 1.4);
  PutStop(b, "east", {"L2", {"", {5.0, 3.0}, {6.2, 3.0}}, {5.6, 2.0, M_PI / 2}});  // replaces east's stop on L2
  ASSERT_EQ(b.lifts[0].stops.size(), 2u);
  EXPECT_EQ(b.lifts[0].stops[1].door.b.x(), 6.2);
  EXPECT_NO_THROW(ValidateStop(b, b.lifts[1].stops[0]));
  EXPECT_THROW(ValidateStop(b, {"L9", {"", {0, 0}, {1, 0}}, {0.5, -0.8, 0.0}}), std::invalid_argument);
  EXPECT_THROW(ValidateStop(b, {"L1", {"", {0, 0}, {0.1, 0}}, {0.5, -0.8, 0.0}}), std::invalid_argument);
}

TEST(LiftsTest, TheCarIsBehindTheDoorFacingIn) {
  const Building b = TurnedFloors();
  const Lift& lift = b.lifts[0];
  const Pose2 car1 = CarPose(lift, lift.stops[0]);
  EXPECT_NEAR(car1.x_m, 2.7, 1e-12);
  EXPECT_NEAR(car1.y_m, 0.5, 1e-12);
  EXPECT_NEAR(car1.yaw_rad, 0.0, 1e-12);
  const Pose2 car2 = CarPose(lift, lift.stops[1]);
  EXPECT_NEAR(car2.x_m, 5.5, 1e-12);
  EXPECT_NEAR(car2.y_m, 3.7, 1e-12);
  EXPECT_NEAR(car2.yaw_rad, M_PI / 2, 1e-12);
}

// The robot driven by the ride's twists (odometry = map pose on L1, exact), the lift answering like a building's.
struct RideRun {
  Building building = TurnedFloors();
  LiftRide ride{LiftOptions{}, building.lifts[0], "L1", "L2", 0.0};
  Pose2 pose{1.0, 0.5, 0.0};  // map frame of the floor the robot is on
  Pose2 odom{1.0, 0.5, 0.0};
  LiftReport report = At("L3", false);
  std::vector<LiftRequest> requests;
  std::optional<std::pair<std::string, Pose2>> switched;
  double now_s = 0.0;

  LiftStep Step(const std::vector<Eigen::Vector2d>* scan) {
    now_s += 0.1;
    LiftStep step = ride.Update(now_s, pose, odom, scan, &report);
    requests.insert(requests.end(), step.requests.begin(), step.requests.end());
    if (step.switch_floor) {
      switched = step.switch_floor;
      pose = step.switch_floor->second;
    }
    pose = DriveArc(pose, step.twist, 0.1);
    odom = DriveArc(odom, step.twist, 0.1);
    return step;
  }
};

TEST(LiftsTest, ARideCallsWaitsForAnEmptyCarBoardsRidesAndLeavesOnTheOtherFloor) {
  RideRun run;
  const std::vector<LiftRequest> first = run.ride.Begin();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].floor, "L1");
  const std::vector<Eigen::Vector2d> empty;
  // Nobody in the car but its back wall (3.4 m ahead) and its sides.
  const std::vector<Eigen::Vector2d> walls = {{2.4, 0.0}, {2.4, 0.1}, {1.5, 0.69}, {1.5, -0.69}};
  // Someone standing in it, 1.5 m ahead.
  std::vector<Eigen::Vector2d> person;
  for (int i = 0; i < 10; ++i) person.push_back({1.5, -0.1 + 0.02 * i});
  for (int i = 0; i < 5; ++i) EXPECT_EQ(run.Step(&walls).phase, LiftPhase::kCalling);
  run.report = At("L1", true);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(run.Step(&person).phase, LiftPhase::kWaitingForEmpty);
  LiftStep step;
  for (int i = 0; i < 3; ++i) step = run.Step(&walls);
  EXPECT_EQ(step.phase, LiftPhase::kBoarding);
  for (int i = 0; i < 400 && step.phase == LiftPhase::kBoarding; ++i) step = run.Step(&empty);
  ASSERT_EQ(step.phase, LiftPhase::kRiding);
  EXPECT_NEAR(run.pose.x_m, 2.7, 0.05);  // at the car's centre
  EXPECT_NEAR(run.pose.y_m, 0.5, 0.05);
  ASSERT_EQ(run.requests.size(), 1u);
  EXPECT_EQ(run.requests[0].floor, "L2");
  // The door closes, the car goes up; the door opens on L2.
  run.report = At("L1", false, true);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(run.Step(&empty).phase, LiftPhase::kRiding);
  run.report = At("L2", true);
  step = run.Step(&empty);
  ASSERT_TRUE(run.switched);
  EXPECT_EQ(run.switched->first, "L2");
  EXPECT_NEAR(run.switched->second.x_m, 5.5, 0.06);
  EXPECT_NEAR(run.switched->second.y_m, 3.7, 0.06);
  EXPECT_NEAR(run.switched->second.yaw_rad, M_PI / 2, 0.06);
  for (int i = 0; i < 600 && step.phase == LiftPhase::kLeaving; ++i) step = run.Step(&empty);
  ASSERT_EQ(step.phase, LiftPhase::kDone);
  // At the lobby on L2, facing away from the door; the lift released.
  EXPECT_NEAR(run.pose.x_m, 5.5, 0.05);
  EXPECT_NEAR(run.pose.y_m, 2.0, 0.05);
  EXPECT_NEAR(std::abs(WrapAngle(run.pose.yaw_rad + M_PI / 2)), 0.0, 0.06);
  ASSERT_EQ(run.requests.size(), 2u);
  EXPECT_TRUE(run.requests[1].release);
  EXPECT_TRUE(run.ride.Abandon().empty());  // released once
}

TEST(LiftsTest, ARefusalATimeoutOrAnOccupiedCarEndTheRideAndReleaseTheLift) {
  {
    RideRun run;
    run.report = At("L1", false);
    run.report.refused = true;
    run.report.detail = "out of service";
    const LiftStep step = run.Step(nullptr);
    EXPECT_EQ(step.phase, LiftPhase::kFailed);
    EXPECT_EQ(step.error, "lift east refused: out of service");
    ASSERT_EQ(step.requests.size(), 1u);
    EXPECT_TRUE(step.requests[0].release);
  }
  {
    RideRun run;
    LiftStep step;
    for (int i = 0; i < 1300 && step.phase != LiftPhase::kFailed; ++i) step = run.Step(nullptr);
    EXPECT_EQ(step.phase, LiftPhase::kFailed);
    EXPECT_NE(step.error.find("did not come to floor L1"), std::string::npos);
    EXPECT_NEAR(run.now_s, 120.1, 0.2);
  }
  {
    RideRun run;
    run.report = At("L1", true);
    std::vector<Eigen::Vector2d> person;
    for (int i = 0; i < 10; ++i) person.push_back({1.5, 0.02 * i});
    LiftStep step;
    for (int i = 0; i < 700 && step.phase != LiftPhase::kFailed; ++i) step = run.Step(&person);
    EXPECT_EQ(step.phase, LiftPhase::kFailed);
    EXPECT_NE(step.error.find("stayed occupied"), std::string::npos);
    EXPECT_NEAR(run.pose.x_m, 1.0, 1e-9);  // never moved
  }
  EXPECT_THROW(LiftRide(LiftOptions{}, TurnedFloors().lifts[0], "L1", "L3", 0.0), std::invalid_argument);
  EXPECT_THROW(Validate(LiftOptions{.speed_mps = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
