#include "nav/policy/flmc.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace corridor::nav {
namespace {

constexpr double kFar = std::numeric_limits<double>::infinity();

FlmcOutput Drive(Flmc& flmc, double bearing, double distance, double left = kFar, double front = kFar,
                 double right = kFar) {
  return flmc.Step({bearing, distance, left, front, right});
}

TEST(FlmcTest, AWaypointAheadAndFarIsDrivenAtFullSpeed) {
  Flmc flmc{FlmcOptions{}};
  const FlmcOutput out = Drive(flmc, 0.0, 3.0);
  EXPECT_EQ(out.mode, FlmcMode::kMotion);
  EXPECT_GT(out.twist.linear_mps, 0.8 * 0.26);
  EXPECT_NEAR(out.twist.angular_rps, 0.0, 1e-9);
}

TEST(FlmcTest, ItTurnsTowardTheWaypointAndMirrorsLeftAndRight) {
  Flmc flmc{FlmcOptions{}};
  double last = 0.0;
  for (double bearing : {0.2, 0.5, 1.0, 2.0}) {
    const double left = Drive(flmc, bearing, 2.0).twist.angular_rps;
    const double right = Drive(flmc, -bearing, 2.0).twist.angular_rps;
    EXPECT_GT(left, last) << bearing;  // the more off, the faster it turns
    EXPECT_NEAR(left, -right, 1e-9) << bearing;
    last = left;
  }
  // Facing well away it turns before it drives.
  EXPECT_EQ(Drive(flmc, 2.5, 2.0).twist.linear_mps, 0.0);
}

TEST(FlmcTest, ItSlowsAsItNearsAndStopsAtTheWaypoint) {
  Flmc flmc{FlmcOptions{}};
  double last = 1.0;
  for (double distance : {2.5, 1.5, 0.9, 0.45, 0.2, 0.08}) {
    const double v = Drive(flmc, 0.0, distance).twist.linear_mps;
    EXPECT_LE(v, last + 1e-12) << distance;
    EXPECT_GT(v, 0.0) << distance;
    last = v;
  }
  EXPECT_EQ(Drive(flmc, 1.0, 0.02).twist.angular_rps, 0.0);  // within stop_within_m: no command at all
  // The rules' own stop, with nothing in front of them: a stop defuzzifies to 0, not to half a triangle's centroid.
  FlmcOptions engine_only;
  engine_only.stop_within_m = 0.0;
  Flmc rules(engine_only);
  const FlmcOutput there = Drive(rules, 0.3, 0.005);
  EXPECT_EQ(there.twist.linear_mps, 0.0);
  EXPECT_NEAR(there.twist.angular_rps, 0.0, 1e-12);
}

TEST(FlmcTest, NearAWaypointBehindItTurnsOnTheSpot) {
  Flmc flmc{FlmcOptions{}};
  const FlmcOutput out = Drive(flmc, -2.0, 0.3);
  EXPECT_EQ(out.mode, FlmcMode::kRotation);
  EXPECT_EQ(out.twist.linear_mps, 0.0);
  EXPECT_LT(out.twist.angular_rps, -0.5);
}

TEST(FlmcTest, AnObstacleAheadIsAvoidedTowardTheFreerSide) {
  Flmc flmc{FlmcOptions{}};
  // Blocked ahead and on the right, open on the left: stop and turn left.
  const FlmcOutput left = Drive(flmc, 0.0, 3.0, 2.0, 0.25, 0.3);
  EXPECT_EQ(left.mode, FlmcMode::kAvoidance);
  EXPECT_EQ(left.twist.linear_mps, 0.0);
  EXPECT_GT(left.twist.angular_rps, 0.5);
  // The mirror image.
  const FlmcOutput right = Drive(flmc, 0.0, 3.0, 0.3, 0.25, 2.0);
  EXPECT_NEAR(right.twist.angular_rps, -left.twist.angular_rps, 1e-9);
  // Something near on the left only: drive on, edging right.
  const FlmcOutput edge = Drive(flmc, 0.0, 3.0, 0.25, 2.0, 2.0);
  EXPECT_GT(edge.twist.linear_mps, 0.0);
  EXPECT_LT(edge.twist.angular_rps, 0.0);
}

// ASNS's Table 8 measure on the controller alone: a unicycle driven by the motion and rotation controllers from
// random poses 1-4 m from a goal, goals behind included, stops within 5 cm of it.
TEST(FlmcTest, FromAnyPoseItStopsWithinFiveCentimetresOfTheGoal) {
  Flmc flmc{FlmcOptions{}};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> range(1.0, 4.0);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  const double dt = 0.05;
  for (int trial = 0; trial < 50; ++trial) {
    const double r = range(rng);
    const double a = angle(rng);
    Pose2 robot{r * std::cos(a), r * std::sin(a), angle(rng)};
    double still_s = 0.0;
    double t = 0.0;
    for (; t < 120.0 && still_s < 1.0; t += dt) {
      const double distance = std::hypot(robot.x_m, robot.y_m);
      const double bearing = std::remainder(std::atan2(-robot.y_m, -robot.x_m) - robot.yaw_rad, 2.0 * std::numbers::pi);
      const Twist2 command = flmc.Step({bearing, distance, kFar, kFar, kFar}).twist;
      still_s = command.linear_mps == 0.0 && std::abs(command.angular_rps) < 1e-6 ? still_s + dt : 0.0;
      robot = DriveArc(robot, command, dt);
    }
    EXPECT_LT(std::hypot(robot.x_m, robot.y_m), 0.05) << "trial " << trial << " after " << t << " s";
    EXPECT_LT(t, 60.0) << "trial " << trial;
  }
}

TEST(FlmcTest, RuleBasesThatCannotRunAreClearErrors) {
  const auto message = [](FlmcOptions o) {
    try {
      Flmc flmc(o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("built");
  };
  FlmcOptions o;
  o.avoidance_fll = DefaultFlmcRules("motion");  // the wrong controller's variables
  EXPECT_EQ(message(o), "flmc avoidance: no input variable 'left'");
  o = {};
  o.rotation_fll =
      "Engine: rotation\nInputVariable: bearing\n  range: -3 3\nRuleBlock: r\n  rule: if bearing is XX then";
  EXPECT_NE(message(o).find("flmc rotation: "), std::string::npos);
  o = {};
  o.max_linear_mps = 0.0;
  EXPECT_EQ(message(o), "flmc: the top speeds must be positive");
  EXPECT_THROW(DefaultFlmcRules("steering"), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
