#include "nav/policy/evasion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

namespace corridor::nav {
namespace {

// Where the robot is heading: 5 m on along its start heading.
const Eigen::Vector2d kTarget(5.0, 0.0);

TrackedObject Person(const Eigen::Vector2d& at, const Eigen::Vector2d& velocity) {
  TrackedObject o;
  o.position = at;
  o.velocity = velocity;
  o.radius_m = 0.2;
  o.moving = velocity.norm() > 0.0;
  o.points = 50;
  return o;
}

// The closest distance between the robot's and a person's centres while the robot, driven by Evasion on every
// 1/18 s step from `command`, and the person, walking straight at constant velocity (and turning round at turn_s),
// move for `seconds`.
double ClosestApproach(Evasion evasion, Pose2 robot, const Twist2& command, Eigen::Vector2d person,
                       Eigen::Vector2d velocity, const std::vector<Eigen::Vector2d>& walls, double seconds,
                       bool* evaded = nullptr, double turn_s = std::numeric_limits<double>::infinity()) {
  const double dt = 1.0 / 18.0;
  double closest = (person - robot.translation()).norm();
  for (double t = 0.0; t < seconds; t += dt) {
    if (t >= turn_s && t < turn_s + dt) velocity = -velocity;
    // The laser sees the near side of the person: report the centroid there, as the tracker would.
    const Eigen::Vector2d seen = person - 0.16 * (person - robot.translation()).normalized();
    const EvasionResult r = evasion.Check(robot, command, kTarget, {Person(seen, velocity)}, walls, nullptr);
    if (evaded != nullptr) *evaded = *evaded || r.evading;
    robot = DriveArc(robot, r.twist, dt);
    person += dt * velocity;
    closest = std::min(closest, (person - robot.translation()).norm());
  }
  return closest;
}

TEST(EvasionTest, NothingMovingOrNothingComingLeavesTheCommandAlone) {
  Evasion evasion{EvasionOptions{}};
  const Pose2 robot{0.0, 0.0, 0.0};
  const Twist2 command{0.26, 0.1};
  EXPECT_FALSE(evasion.Check(robot, command, kTarget, {}, {}, nullptr).evading);
  // Standing people are walls' business (static points), not evasion's.
  EXPECT_FALSE(evasion.Check(robot, command, kTarget, {Person({1.0, 0.0}, {0.0, 0.0})}, {}, nullptr).evading);
  // Walking away (beyond turn_reach_m, or not with the robot in their wake), or crossing well ahead.
  EXPECT_FALSE(evasion.Check(robot, command, kTarget, {Person({3.5, 0.0}, {0.8, 0.0})}, {}, nullptr).evading);
  EXPECT_FALSE(evasion.Check(robot, command, kTarget, {Person({1.0, 1.0}, {0.0, 0.8})}, {}, nullptr).evading);
  EXPECT_FALSE(evasion.Check(robot, command, kTarget, {Person({4.0, -3.0}, {0.0, 0.8})}, {}, nullptr).evading);
  const EvasionResult unchanged =
      evasion.Check(robot, command, kTarget, {Person({4.0, -3.0}, {0.0, 0.8})}, {}, nullptr);
  EXPECT_EQ(unchanged.twist.linear_mps, command.linear_mps);
  EXPECT_EQ(unchanged.twist.angular_rps, command.angular_rps);
}

TEST(EvasionTest, SomeoneWalkingIntoTheRobotFromAnySideIsAvoided) {
  // A person who does not see the robot walks at 0.8 m/s straight through where the robot is waiting, from 3 m
  // away and from every direction.
  EvasionOptions o;
  o.max_reverse_mps = 0.26;
  Evasion evasion{o};
  const double touching = o.robot_radius_m + 0.25;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  for (int k = 0; k < 16; ++k) {
    const double from = k * std::numbers::pi / 8.0;
    const Eigen::Vector2d direction(std::cos(from), std::sin(from));
    const Eigen::Vector2d start = 3.0 * direction + offset(rng) * Eigen::Vector2d(-direction.y(), direction.x());
    bool evaded = false;
    const double closest =
        ClosestApproach(evasion, {0.0, 0.0, 0.0}, {0.0, 0.0}, start, -0.8 * direction, {}, 8.0, &evaded);
    EXPECT_TRUE(evaded) << "from " << from;
    EXPECT_GT(closest, touching) << "from " << from;
  }
}

TEST(EvasionTest, SomeoneWalkingAtTheRobotWhileItDrivesIsAvoided) {
  // The same people, aimed at where the robot started while it drives on at its top speed: head-on and from
  // behind, it must turn out of their line.
  EvasionOptions o;
  o.max_reverse_mps = 0.26;
  Evasion evasion{o};
  for (int k = 0; k < 16; ++k) {
    const double from = k * std::numbers::pi / 8.0;
    const Eigen::Vector2d direction(std::cos(from), std::sin(from));
    const double closest =
        ClosestApproach(evasion, {0.0, 0.0, 0.0}, {0.26, 0.0}, 3.0 * direction, -0.8 * direction, {}, 8.0);
    EXPECT_GT(closest, o.robot_radius_m + 0.25) << "from " << from;
  }
}

TEST(EvasionTest, WithoutEvasionTheSameEncountersCollide) {
  // The check above can fail: standing still, every one of those people walks into the robot.
  int hits = 0;
  for (int k = 0; k < 16; ++k) {
    const double from = k * std::numbers::pi / 8.0;
    const Eigen::Vector2d direction(std::cos(from), std::sin(from));
    const Pose2 robot{0.0, 0.0, 0.0};
    Eigen::Vector2d person = 3.0 * direction;
    double closest = 1e9;
    for (double t = 0.0; t < 8.0; t += 1.0 / 18.0) {
      person -= 0.8 / 18.0 * direction;
      closest = std::min(closest, (person - robot.translation()).norm());
    }
    hits += closest < 0.45 ? 1 : 0;
  }
  EXPECT_EQ(hits, 16);
}

TEST(EvasionTest, TheRobotDoesNotFollowSomeoneSoCloselyThatTheirTurningRoundHitsIt) {
  // Someone has just crossed into the robot's way 0.9 m ahead and walks on along it; a second later they turn
  // round on the spot (the end of their walk) and come straight back.
  EvasionOptions o;
  o.max_reverse_mps = 0.26;
  const double touching = o.robot_radius_m + 0.25;
  const Pose2 robot{0.0, 0.0, 0.0};
  for (const double turn_s : {1.0, 1.5, 2.5}) {
    EXPECT_GT(ClosestApproach(Evasion{o}, robot, {0.26, 0.0}, {0.9, 0.0}, {0.8, 0.0}, {}, 6.0, nullptr, turn_s),
              touching)
        << "turning after " << turn_s << " s";
  }
  // Seeing the turn only once it happens is too late for a robot at a third of a person's speed.
  EvasionOptions no_turns = o;
  no_turns.turn_reach_m = 0.0;
  EXPECT_LT(ClosestApproach(Evasion{no_turns}, robot, {0.26, 0.0}, {0.9, 0.0}, {0.8, 0.0}, {}, 6.0, nullptr, 1.0),
            touching);
}

TEST(EvasionTest, SomeoneWalkingToTheKnownEndOfTheirWalkIsExpectedToTurnThere) {
  // People pace: the tracker reports where a person turned round before (TrackedObject::turn_at).
  Evasion evasion{EvasionOptions{}};
  const Pose2 robot{0.0, 0.0, 0.0};
  const Twist2 command{0.26, 0.0};
  const auto pacing = [](const Eigen::Vector2d& at, const Eigen::Vector2d& velocity,
                         const std::optional<Eigen::Vector2d>& end) {
    TrackedObject o = Person(at, velocity);
    o.turn_at = end;
    return std::vector<TrackedObject>{o};
  };
  // Walking at the robot's way from the side, but their walk ends 1.2 m short of it: the robot drives on.
  const Eigen::Vector2d side(1.5, -2.5);
  const Eigen::Vector2d up(0.0, 0.8);
  EXPECT_TRUE(evasion.Check(robot, command, kTarget, pacing(side, up, std::nullopt), {}, nullptr).evading);
  const EvasionResult on =
      evasion.Check(robot, command, kTarget, pacing(side, up, Eigen::Vector2d(1.5, -1.2)), {}, nullptr);
  EXPECT_FALSE(on.evading);
  EXPECT_EQ(on.twist.linear_mps, command.linear_mps);
  // Walking away along the robot's way 1 m ahead: with the end of their walk far off the robot follows, with it
  // just ahead of them it does not (they are about to come back).
  const Eigen::Vector2d ahead(1.0, 0.0);
  const Eigen::Vector2d away(0.8, 0.0);
  const auto follows = [&](const Eigen::Vector2d& end) {
    return !evasion.Check(robot, command, kTarget, pacing(ahead, away, end), {}, nullptr).evading;
  };
  EXPECT_TRUE(follows({6.0, 0.0}));
  EXPECT_FALSE(follows({1.6, 0.0}));
}

TEST(EvasionTest, TheWayOutDoesNotBackIntoAWall) {
  // A wall 0.35 m behind the robot: backing away from someone coming head-on is not allowed, stepping aside is.
  EvasionOptions o;
  o.max_reverse_mps = 0.26;
  Evasion evasion{o};
  std::vector<Eigen::Vector2d> wall;
  for (double y = -2.0; y <= 2.0; y += 0.05) wall.emplace_back(-0.35, y);
  const Pose2 robot{0.0, 0.0, 0.0};
  const EvasionResult r = evasion.Check(robot, {0.0, 0.0}, kTarget, {Person({2.4, 0.0}, {-0.8, 0.0})}, wall, nullptr);
  EXPECT_TRUE(r.evading);
  EXPECT_GE(r.twist.linear_mps, 0.0);
  EXPECT_GT((ClosestApproach(evasion, robot, {0.0, 0.0}, {2.6, 0.05}, {-0.8, 0.0}, wall, 6.0)),
            o.robot_radius_m + 0.25);
}

TEST(EvasionTest, ARobotThatSeesOnlyAheadNeverBacks) {
  // Someone coming head-on: with a laser, backing away is one way out; seeing only ahead (a depth camera), what is
  // behind is unknown and the robot steps aside instead, and still keeps clear.
  EvasionOptions o;
  o.max_reverse_mps = 0.26;
  const EvasionOptions forward = ForForwardView(o);
  EXPECT_EQ(forward.max_reverse_mps, 0.0);
  EXPECT_EQ(forward.max_linear_mps, o.max_linear_mps);
  Evasion evasion{forward};
  const Pose2 robot{0.0, 0.0, 0.0};
  for (int k = 0; k < 18; ++k) {
    const EvasionResult r =
        evasion.Check(robot, {0.0, 0.0}, kTarget, {Person({2.4 - 0.05 * k, 0.0}, {-0.8, 0.0})}, {}, nullptr);
    EXPECT_GE(r.twist.linear_mps, 0.0);
  }
  EXPECT_GT((ClosestApproach(Evasion{forward}, robot, {0.0, 0.0}, {2.6, 0.05}, {-0.8, 0.0}, {}, 6.0)),
            o.robot_radius_m + 0.25);
}

TEST(EvasionTest, BadOptionsAreRefused) {
  EvasionOptions o;
  o.step_s = 0.0;
  EXPECT_THROW(Evasion{o}, std::invalid_argument);
  o = {};
  o.static_horizon_s = 10.0;
  EXPECT_THROW(Evasion{o}, std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
