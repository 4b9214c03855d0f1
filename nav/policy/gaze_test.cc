#include "nav/policy/gaze.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A leg along x from the robot at the origin, then turning left at x = 2.
GazeInput Bend() {
  GazeInput in;
  in.map_T_base = {0.0, 0.0, 0.0};
  in.path = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 2.0}, {1.0, 5.0}};
  in.speed_mps = 0.0;
  return in;
}

TEST(GazeTest, WithNoPathItLooksStraightAhead) {
  GazeInput in;
  in.obstacles = {{2.0, 0.0}};
  const GazeDecision d = DecideGaze(in, GazeOptions{});
  EXPECT_EQ(d.reason, GazeReason::kAhead);
  EXPECT_EQ(d.pan_rad, 0.0);
}

TEST(GazeTest, ItLooksIntoABendBeforeTheRobotTurns) {
  GazeOptions options;
  options.lookahead_m = 1.5;  // 1 m along x, then 0.5 m up: the point (1, 0.5)
  options.keep_ahead_deg = 180.0;
  const GazeDecision d = DecideGaze(Bend(), options);
  EXPECT_EQ(d.reason, GazeReason::kPath);
  ASSERT_TRUE(d.looked_at.has_value());
  EXPECT_NEAR(d.looked_at->x(), 1.0, 1e-9);
  EXPECT_NEAR(d.looked_at->y(), 0.5, 1e-9);
  EXPECT_NEAR(d.pan_rad, std::atan2(0.5, 1.0), 1e-9);
  // A robot already heading left sees the same point to its right.
  GazeInput turned = Bend();
  turned.map_T_base.yaw_rad = 90.0 * kDeg;
  EXPECT_NEAR(DecideGaze(turned, options).pan_rad, std::atan2(0.5, 1.0) - 90.0 * kDeg, 1e-9);
}

TEST(GazeTest, TheNearestObstacleInTheBandOnThePathAheadTakesTheGaze) {
  GazeInput in = Bend();
  in.obstacles = {
      {0.5, 0.0},   // on the path but nearer than 0.9 m: the lanes see it
      {1.2, 3.0},   // on the path, 3.2 m away
      {1.1, 1.5},   // on the path, 1.9 m away: the nearest in the band
      {-2.0, 0.0},  // 2 m away but behind, off the path ahead
      {3.5, 0.0},   // ahead in x but 2.5 m off the bent path
  };
  GazeOptions options;
  options.keep_ahead_deg = 90.0;
  const GazeDecision d = DecideGaze(in, options);
  EXPECT_EQ(d.reason, GazeReason::kObstacle);
  ASSERT_TRUE(d.looked_at.has_value());
  EXPECT_NEAR(d.looked_at->x(), 1.1, 1e-9);
  EXPECT_NEAR(d.pan_rad, std::atan2(1.5, 1.1), 1e-9);
}

TEST(GazeTest, WhileItFollowsAPathTheCameraKeepsTheWayAheadInView) {
  GazeInput in = Bend();
  in.obstacles = {{1.0, 1.5}};  // 56 degrees to the left
  GazeOptions options;
  options.keep_ahead_deg = 25.0;
  // Driving or stopped (a robot stopped by blind lanes must see them again to start).
  for (const double speed : {0.3, 0.0}) {
    in.speed_mps = speed;
    EXPECT_NEAR(DecideGaze(in, options).pan_rad, 25.0 * kDeg, 1e-9);
  }
  options.keep_ahead_deg = 180.0;
  EXPECT_NEAR(DecideGaze(in, options).pan_rad, std::atan2(1.5, 1.0), 1e-9);
}

TEST(GazeTest, NearTheGoalAndStillItLooksBackAsFarAsTheServoTurns) {
  GazeInput in;
  in.map_T_base = {4.6, 0.0, 0.0};
  in.path = {{0.0, 0.0}, {5.0, 0.0}};
  GazeOptions options;
  options.goal_near_m = 0.5;
  options.min_pan_rad = -120.0 * kDeg;
  options.max_pan_rad = 150.0 * kDeg;
  GazeDecision d = DecideGaze(in, options);
  EXPECT_EQ(d.reason, GazeReason::kBackward);
  EXPECT_NEAR(d.pan_rad, 150.0 * kDeg, 1e-9);
  in.speed_mps = 0.2;  // still arriving: the way ahead first
  d = DecideGaze(in, options);
  EXPECT_EQ(d.reason, GazeReason::kPath);
  EXPECT_NEAR(d.pan_rad, 0.0, 1e-9);
}

TEST(GazeTest, BadOptionsAreRefused) {
  GazeOptions o;
  o.obstacle_max_m = 0.5;
  EXPECT_THROW(ValidateGazeOptions(o), std::invalid_argument);
  o = GazeOptions{};
  o.min_pan_rad = 0.1;
  EXPECT_THROW(ValidateGazeOptions(o), std::invalid_argument);
  EXPECT_NO_THROW(ValidateGazeOptions(GazeOptions{}));
}

}  // namespace
}  // namespace corridor::nav
