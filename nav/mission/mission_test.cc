#include "nav/mission/mission.h"

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

MissionGoal Goal(Pose2 pose, bool has_yaw, std::string place) {
  MissionGoal goal;
  goal.pose = pose;
  goal.has_yaw = has_yaw;
  goal.place = std::move(place);
  return goal;
}

Mission ThreeStops() {
  return Mission("m1", {Goal({1, 0, 0}, false, ""), Goal({1, 1, 0}, true, "kitchen"), Goal({0, 1, 0}, false, "")}, 0.5);
}

TEST(MissionTest, PauseResumeCancelFollowTheAllowedTransitions) {
  Mission m = ThreeStops();
  EXPECT_FALSE(m.Resume());
  EXPECT_TRUE(m.Pause());
  EXPECT_FALSE(m.Pause());
  EXPECT_EQ(m.status(), MissionStatus::kPaused);
  EXPECT_TRUE(m.Resume());
  EXPECT_TRUE(m.Cancel());
  EXPECT_FALSE(m.Cancel());
  EXPECT_FALSE(m.Resume());
  EXPECT_EQ(m.status(), MissionStatus::kCanceled);
}

TEST(MissionTest, WaypointsInOrderThenSuccessAndProgressGrows) {
  Mission m = ThreeStops();
  EXPECT_NEAR(m.Progress(1.0, 1.0), 0.0, 1e-9);
  EXPECT_NEAR(m.Progress(0.5, 1.0), 0.5 / 3.0, 1e-9);
  m.GoalReached();
  EXPECT_EQ(m.current(), 1u);
  EXPECT_EQ(m.current_goal().place, "kitchen");
  EXPECT_NEAR(m.Progress(1.0, 1.0), 1.0 / 3.0, 1e-9);
  // ETA: 0.5 m left on this leg plus the 1 m straight line to the last goal, at 0.5 m/s.
  EXPECT_NEAR(m.EtaSeconds(0.5, 0.5), 3.0, 1e-9);
  m.GoalReached();
  m.GoalReached();
  EXPECT_EQ(m.status(), MissionStatus::kSucceeded);
  EXPECT_EQ(m.Progress(0.0, 0.0), 1.0);
  EXPECT_FALSE(m.Pause());
}

TEST(MissionTest, FailureKeepsItsReasonAndEndsTheMission) {
  Mission m = ThreeStops();
  m.Fail("goal occupied");
  EXPECT_EQ(m.status(), MissionStatus::kFailed);
  EXPECT_EQ(m.error(), "goal occupied");
  EXPECT_FALSE(m.Cancel());
  EXPECT_THROW(Mission("x", {}, 1.0), std::invalid_argument);
}

TEST(MissionTest, ExtendingAddsGoalsUntilItHasFinished) {
  Mission m = ThreeStops();
  m.GoalReached();
  EXPECT_TRUE(m.Extend({Goal({2, 2, 0}, false, "")}));
  m.GoalReached();
  m.GoalReached();
  EXPECT_EQ(m.status(), MissionStatus::kActive);
  EXPECT_EQ(m.current_goal().pose.x_m, 2.0);
  m.GoalReached();
  EXPECT_EQ(m.status(), MissionStatus::kSucceeded);
  EXPECT_FALSE(m.Extend({Goal({3, 3, 0}, false, "")}));
  EXPECT_EQ(m.goals().size(), 4u);
}

}  // namespace
}  // namespace corridor::nav
