#include "nav/policy/polar_controller.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "nav/policy/path_follower.h"

namespace corridor::nav {
namespace {

TEST(PolarControllerTest, GainsAreValidatedAgainstTheStabilityConditions) {
  EXPECT_NO_THROW(ValidateGains({0.6, 2.0, -0.8}));
  EXPECT_THROW(ValidateGains({0.0, 2.0, -0.8}), std::invalid_argument);  // k_rho > 0
  EXPECT_THROW(ValidateGains({0.6, 2.0, 0.1}), std::invalid_argument);   // k_beta < 0
  EXPECT_THROW(ValidateGains({0.6, 0.5, -0.8}), std::invalid_argument);  // k_alpha - k_rho > 0
}

TEST(PolarControllerTest, GoalBehindIsReachedInReverse) {
  const PolarCommand c = PolarControl({0, 0, 0}, {-1.0, 0.0, 0.0}, PolarGains{}, true);
  EXPECT_TRUE(c.reversing);
  EXPECT_LT(c.twist.linear_mps, 0.0);
  EXPECT_NEAR(c.twist.angular_rps, 0.0, 1e-9);
  const PolarCommand forward_only = PolarControl({0, 0, 0}, {-1.0, 0.0, 0.0}, PolarGains{}, false);
  EXPECT_FALSE(forward_only.reversing);
  EXPECT_GT(std::abs(forward_only.alpha), 3.0);
}

// Integrates the closed loop with unicycle kinematics until within 5 mm and 1 degree (a controller stops there:
// at rho ~ 1e-15 the bearing is numerical noise).
Pose2 Simulate(Pose2 robot, const Pose2& goal, bool reverse, double seconds) {
  constexpr double kDt = 0.01;
  for (int i = 0; i < static_cast<int>(seconds / kDt); ++i) {
    const PolarCommand c = PolarControl(robot, goal, PolarGains{}, reverse);
    if (c.rho < 0.005 && std::abs(WrapAngle(robot.yaw_rad - goal.yaw_rad)) < 0.0175) break;
    const Twist2 u = c.twist;
    robot = robot * Pose2{u.linear_mps * kDt, 0.0, u.angular_rps * kDt};
  }
  return robot;
}

TEST(PolarControllerTest, ConvergesToTheGoalPoseFromRandomStarts) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-3.0, 3.0);
  std::uniform_real_distribution<double> ang(-std::numbers::pi, std::numbers::pi);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 goal{pos(rng), pos(rng), ang(rng)};
    const Pose2 end = Simulate({pos(rng), pos(rng), ang(rng)}, goal, trial % 2 == 0, 60.0);
    EXPECT_NEAR(end.x_m, goal.x_m, 0.005);
    EXPECT_NEAR(end.y_m, goal.y_m, 0.005);
    EXPECT_NEAR(WrapAngle(end.yaw_rad - goal.yaw_rad), 0.0, 0.0175);
  }
}

TEST(PathFollowerTest, FollowsAnLShapedPathAndStopsAtTheGoalPose) {
  PathFollower follower(FollowerOptions{});
  std::vector<Waypoint> path(3);
  path[0].pose = {0.0, 0.0, 0.0};
  path[1].pose = {4.0, 0.0, std::numbers::pi / 2.0};
  path[2].pose = {4.0, 3.0, std::numbers::pi};
  path[2].speed_limit_mps = 0.2;  // a slow zone on the second leg (a limit covers the leg into its waypoint)
  follower.SetPath(path);
  Pose2 robot{0.0, 0.0, 0.0};
  constexpr double kDt = 0.02;
  double worst_offset = 0.0;
  double fastest_on_second_leg = 0.0;
  bool done = false;
  for (int i = 0; i < 5000 && !done; ++i) {
    const FollowStep step = follower.Update(robot, 10.0);
    done = step.done;
    EXPECT_LE(std::abs(step.twist.linear_mps), 0.5 + 1e-9);
    if (robot.x_m > 3.9 && robot.y_m > 0.5)
      fastest_on_second_leg = std::max(fastest_on_second_leg, step.twist.linear_mps);
    robot = robot * Pose2{step.twist.linear_mps * kDt, 0.0, step.twist.angular_rps * kDt};
    const double offset = robot.x_m < 3.5 ? std::abs(robot.y_m) : std::abs(robot.x_m - 4.0);
    if (robot.x_m < 3.5 || robot.y_m > 0.5) worst_offset = std::max(worst_offset, offset);
  }
  ASSERT_TRUE(done);
  EXPECT_NEAR(robot.x_m, 4.0, 0.01);
  EXPECT_NEAR(robot.y_m, 3.0, 0.01);
  EXPECT_NEAR(WrapAngle(robot.yaw_rad - std::numbers::pi), 0.0, 0.0175);
  EXPECT_LT(worst_offset, 0.15);
  EXPECT_LE(fastest_on_second_leg, 0.2 + 1e-9);
}

}  // namespace
}  // namespace corridor::nav
