#include "nav/safety/command_gate.h"

#include <cmath>

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

// Four lanes, each blocked at `dead_end_m` (or clear when negative).
std::vector<LaneResult> LanesAt(double dead_end_m) {
  std::vector<LaneResult> lanes;
  for (double offset : {0.15, 0.05, -0.05, -0.15}) {
    LaneResult lane;
    lane.offset_m = offset;
    lane.dead_end = dead_end_m >= 0.0;
    lane.free_distance_m = dead_end_m >= 0.0 ? dead_end_m : 4.0;
    lanes.push_back(lane);
  }
  return lanes;
}

// A gate that has had odometry and clear lanes at `now_s`.
CommandGate Seeing(double now_s, const CommandGateOptions& options = {}) {
  CommandGate gate(options);
  gate.Odometry(now_s, false);
  gate.Sight(now_s, LanesAt(-1.0));
  return gate;
}

TEST(CommandGateTest, TeleopIsAppliedWithinTheDeadmanAndClamped) {
  CommandGate gate = Seeing(10.19);
  const TimedTwist teleop{{2.0, -0.5}, 10.0};
  const GateDecision c = gate.Decide(10.2, &teleop, nullptr);
  EXPECT_EQ(c.mode, ControlMode::kTeleop);
  EXPECT_DOUBLE_EQ(c.twist.linear_mps, gate.options().max_linear_mps);
  EXPECT_DOUBLE_EQ(c.twist.angular_rps, -0.5);
}

TEST(CommandGateTest, DeadmanLapsesAndTheRobotStops) {
  CommandGate gate = Seeing(10.5);
  const TimedTwist teleop{{0.3, 0.0}, 10.0};
  const GateDecision c = gate.Decide(10.0 + gate.options().teleop_deadman_s + 0.01, &teleop, nullptr);
  EXPECT_EQ(c.mode, ControlMode::kIdle);
  EXPECT_EQ(c.twist.linear_mps, 0.0);
  EXPECT_EQ(c.twist.angular_rps, 0.0);
}

TEST(CommandGateTest, TeleopOverridesAMissionAndAStaleMissionIsIgnored) {
  CommandGate gate = Seeing(10.1);
  const TimedTwist teleop{{0.1, 0.0}, 10.0};
  const TimedTwist mission{{0.4, 0.2}, 10.0};
  EXPECT_EQ(gate.Decide(10.1, &teleop, &mission).mode, ControlMode::kTeleop);
  const GateDecision m = gate.Decide(10.1, nullptr, &mission);
  EXPECT_EQ(m.mode, ControlMode::kMission);
  EXPECT_DOUBLE_EQ(m.twist.linear_mps, 0.4);
  gate.Odometry(10.5, false);
  EXPECT_EQ(gate.Decide(10.5, nullptr, &mission).mode, ControlMode::kIdle);
}

TEST(CommandGateTest, ForwardSpeedStopsBeforeWhatTheCameraSeesAndNeedsFreshDepth) {
  const CommandGateOptions o;
  const TimedTwist forward{{0.5, 0.0}, 10.0};
  const auto with = [&](const std::vector<LaneResult>* lanes, double lanes_s) {
    CommandGate gate(o);
    gate.Odometry(10.05, false);
    if (lanes != nullptr) gate.Sight(lanes_s, *lanes);
    return gate.Decide(10.05, &forward, nullptr);
  };
  const auto clear = LanesAt(-1.0);
  EXPECT_DOUBLE_EQ(with(&clear, 10.04).twist.linear_mps, 0.5);
  // A dead-end 0.4 m from the centre is 0.2 m from the front: the speed that stops within it (0.42 m/s).
  const auto near = LanesAt(0.4);
  const GateDecision slowed = with(&near, 10.04);
  EXPECT_LT(slowed.twist.linear_mps, 0.5);
  EXPECT_NEAR(StoppingDistance(slowed.twist.linear_mps, o.stopping), 0.2, 1e-9);
  EXPECT_EQ(slowed.reason, GateReason::kSlowedForObstacle);
  // At the front already: no forward motion at all.
  const auto touching = LanesAt(0.2);
  EXPECT_EQ(with(&touching, 10.04).twist.linear_mps, 0.0);
  // No depth frame for longer than depth_timeout_s, or never: hold forward motion; reversing and turning stay allowed.
  EXPECT_EQ(with(&clear, 10.05 - o.depth_timeout_s - 0.01).twist.linear_mps, 0.0);
  EXPECT_EQ(with(nullptr, 0.0).reason, GateReason::kNoDepth);
  CommandGate blind(o);
  blind.Odometry(10.05, false);
  const TimedTwist back{{-0.3, 0.5}, 10.0};
  const GateDecision reversing = blind.Decide(10.05, &back, nullptr);
  EXPECT_DOUBLE_EQ(reversing.twist.linear_mps, -0.3);
  EXPECT_DOUBLE_EQ(reversing.twist.angular_rps, 0.5);
}

TEST(CommandGateTest, ObstaclePointsOfAnotherFrontEndCapTheSpeedAsLanesDo) {
  CommandGate gate(CommandGateOptions{});
  gate.Odometry(10.0, false);
  // One point beside the corridor (ignored), one in it 0.4 m ahead of the centre.
  gate.Sight(10.0, std::vector<Eigen::Vector2f>{{0.3f, 0.8f}, {0.4f, 0.1f}});
  const TimedTwist forward{{0.5, 0.0}, 10.0};
  const GateDecision c = gate.Decide(10.0, &forward, nullptr);
  EXPECT_NEAR(StoppingDistance(c.twist.linear_mps, gate.options().stopping), 0.2, 1e-6);  // points are floats
  gate.Sight(10.0, std::vector<Eigen::Vector2f>{{0.3f, 0.8f}});
  EXPECT_DOUBLE_EQ(gate.Decide(10.0, &forward, nullptr).twist.linear_mps, 0.5);
}

TEST(CommandGateTest, AfterABumpNothingDrivesOnThatWayForASecondButItMayTurnAndDriveAway) {
  const TimedTwist push{{0.2, 0.3}, 10.0};
  const TimedTwist back{{-0.1, 0.0}, 10.0};
  // Driving `before` when the bumper is pressed at 10.0; then asked for `command` at now_s.
  const auto after_bump = [&](const TimedTwist& before, double now_s, const TimedTwist& command) {
    CommandGate gate = Seeing(9.9);
    const TimedTwist driving{before.twist, 9.9};
    gate.Decide(9.9, nullptr, &driving);
    gate.Odometry(10.0, true);
    gate.Odometry(now_s, false);
    gate.Sight(now_s, LanesAt(-1.0));
    return gate.Decide(now_s, nullptr, &command);
  };
  const GateDecision held = after_bump(push, 10.05, push);
  EXPECT_EQ(held.mode, ControlMode::kMission);
  EXPECT_EQ(held.twist.linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(held.twist.angular_rps, 0.3);
  EXPECT_EQ(held.reason, GateReason::kBumpedForward);
  EXPECT_DOUBLE_EQ(after_bump(push, 10.05, back).twist.linear_mps, -0.1);
  // A second after the bumper let go, forward again.
  EXPECT_DOUBLE_EQ(after_bump(push, 11.25, TimedTwist{push.twist, 11.2}).twist.linear_mps, 0.2);
  // Bumped backing into something: it may drive forward away from it, not back on.
  EXPECT_DOUBLE_EQ(after_bump(back, 10.05, push).twist.linear_mps, 0.2);
  const GateDecision no_back = after_bump(back, 10.05, back);
  EXPECT_EQ(no_back.twist.linear_mps, 0.0);
  EXPECT_EQ(no_back.reason, GateReason::kBumpedBacking);
}

TEST(CommandGateTest, NoOdometryMeansStopWithAReason) {
  const TimedTwist teleop{{0.3, 0.0}, 10.0};
  CommandGate never(CommandGateOptions{});
  CommandGate lapsed = Seeing(9.0);
  for (CommandGate* gate : {&never, &lapsed}) {
    const GateDecision c = gate->Decide(10.1, &teleop, nullptr);
    EXPECT_EQ(c.mode, ControlMode::kStopped);
    EXPECT_EQ(c.twist.linear_mps, 0.0);
    EXPECT_EQ(c.reason, GateReason::kNoOdometry);
  }
}

TEST(CommandGateTest, AFaultStopsTheRobotForTheHoldAndThenItDrivesAgain) {
  CommandGate gate = Seeing(10.0);
  gate.Fault(10.0);
  const auto at = [&](double now_s) {
    gate.Odometry(now_s, false);
    gate.Sight(now_s, LanesAt(-1.0));
    const TimedTwist teleop{{0.3, 0.2}, now_s};
    return gate.Decide(now_s, &teleop, nullptr);
  };
  const GateDecision stopped = at(10.0 + gate.options().fault_hold_s - 0.01);
  EXPECT_EQ(stopped.mode, ControlMode::kStopped);
  EXPECT_EQ(stopped.reason, GateReason::kProtectiveStop);
  EXPECT_EQ(stopped.twist.linear_mps, 0.0);
  EXPECT_EQ(stopped.twist.angular_rps, 0.0);
  const GateDecision again = at(10.0 + gate.options().fault_hold_s + 0.01);
  EXPECT_EQ(again.mode, ControlMode::kTeleop);
  EXPECT_DOUBLE_EQ(again.twist.linear_mps, 0.3);
}

TEST(CommandGateTest, APersonAheadWithinOneAndAHalfMetresHalvesTheSpeedWhileTheReportIsFresh) {
  CommandGate gate = Seeing(10.0);
  const TimedTwist mission{{0.5, 0.1}, 10.0};
  gate.People(10.0, {{1.2, 0.3}});
  GateDecision c = gate.Decide(10.0, nullptr, &mission);
  EXPECT_DOUBLE_EQ(c.twist.linear_mps, 0.5 * gate.options().max_linear_mps);
  EXPECT_DOUBLE_EQ(c.twist.angular_rps, 0.1);
  EXPECT_EQ(c.reason, GateReason::kSlowedForPerson);
  // Beside or behind the robot, or farther than 1.5 m: not slowed.
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.2, 1.0), Eigen::Vector2d(-1.0, 0.0), Eigen::Vector2d(2.0, 0.0)}) {
    gate.People(10.0, {p});
    EXPECT_DOUBLE_EQ(gate.Decide(10.0, nullptr, &mission).twist.linear_mps, 0.5) << p.transpose();
  }
  // A report older than a second no longer slows it.
  gate.People(10.0, {{1.0, 0.0}});
  gate.Odometry(11.2, false);
  gate.Sight(11.2, LanesAt(-1.0));
  const TimedTwist later{{0.5, 0.0}, 11.2};
  EXPECT_DOUBLE_EQ(gate.Decide(11.2, nullptr, &later).twist.linear_mps, 0.5);
}

TEST(CommandGateTest, ADeviceDownOrACliffStopsTheRobotUntilItIsBack) {
  CommandGate gate = Seeing(10.0);
  const TimedTwist teleop{{0.3, 0.4}, 10.0};
  gate.Link(Device::kLaser, false);
  GateDecision c = gate.Decide(10.01, &teleop, nullptr);
  EXPECT_EQ(c.mode, ControlMode::kStopped);
  EXPECT_EQ(c.reason, GateReason::kDeviceDown);
  EXPECT_EQ(c.twist.angular_rps, 0.0);
  ASSERT_TRUE(gate.down());
  EXPECT_STREQ(ToString(*gate.down()), "laser");
  gate.Link(Device::kLaser, true);
  EXPECT_FALSE(gate.down());
  EXPECT_DOUBLE_EQ(gate.Decide(10.02, &teleop, nullptr).twist.linear_mps, 0.3);
  // The base sees no floor: everything stops (backing away included) until the next odometry says it is back.
  gate.Odometry(10.03, false, /*cliff=*/true);
  const TimedTwist back{{-0.2, 0.0}, 10.03};
  c = gate.Decide(10.03, &back, nullptr);
  EXPECT_EQ(c.reason, GateReason::kCliff);
  EXPECT_EQ(c.twist.linear_mps, 0.0);
  gate.Odometry(10.04, false, false);
  EXPECT_DOUBLE_EQ(gate.Decide(10.04, &back, nullptr).twist.linear_mps, -0.2);
}

TEST(CommandGateTest, WithALaserForwardNeedsFreshScans) {
  CommandGateOptions o;
  o.require_laser = true;
  CommandGate gate = Seeing(10.0, o);
  const TimedTwist forward{{0.3, 0.2}, 10.0};
  EXPECT_EQ(gate.Decide(10.0, &forward, nullptr).reason, GateReason::kNoLaser);  // none yet
  gate.Scan(10.0);
  EXPECT_DOUBLE_EQ(gate.Decide(10.0, &forward, nullptr).twist.linear_mps, 0.3);
  gate.Odometry(10.0 + o.laser_timeout_s + 0.01, false);
  gate.Sight(10.0 + o.laser_timeout_s + 0.01, LanesAt(-1.0));
  const GateDecision late = gate.Decide(10.0 + o.laser_timeout_s + 0.01, &forward, nullptr);
  EXPECT_EQ(late.reason, GateReason::kNoLaser);
  EXPECT_EQ(late.twist.linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(late.twist.angular_rps, 0.2);  // turning stays allowed
}

TEST(CommandGateTest, WithoutACameraTheLasersLanesAreTheSightAndGoStaleWithTheLaser) {
  CommandGateOptions o;
  o.require_laser = true;
  o.require_depth = false;
  CommandGate gate(o);
  gate.Odometry(10.0, false);
  gate.Scan(10.0);
  gate.Sight(10.0, LanesAt(-1.0));
  // Older than the depth timeout, younger than the laser's: still fresh.
  const double later = 10.0 + o.depth_timeout_s + 0.05;
  gate.Odometry(later, false);
  const TimedTwist asked{{0.3, 0.0}, later};
  EXPECT_DOUBLE_EQ(gate.Decide(later, &asked, nullptr).twist.linear_mps, 0.3);
  const double stale = 10.0 + o.laser_timeout_s + 0.01;
  gate.Odometry(stale, false);
  const TimedTwist late{{0.3, 0.0}, stale};
  const GateDecision c = gate.Decide(stale, &late, nullptr);
  EXPECT_EQ(c.twist.linear_mps, 0.0);
  EXPECT_EQ(c.reason, GateReason::kNoLaser);
}

TEST(CommandGateTest, TheNextExpiryIsTheEarliestWatchdogStillRunning) {
  CommandGateOptions o;
  o.require_laser = true;
  CommandGate gate(o);
  EXPECT_TRUE(std::isinf(gate.NextExpiry(10.0)));  // nothing seen: nothing to go stale
  gate.Odometry(10.0, false);
  gate.Sight(10.01, LanesAt(-1.0));
  gate.Scan(10.02);
  EXPECT_DOUBLE_EQ(gate.NextExpiry(10.0), 10.0 + o.odometry_timeout_s);
  gate.Odometry(10.05, false);
  EXPECT_DOUBLE_EQ(gate.NextExpiry(10.05), 10.01 + o.depth_timeout_s);
  // Past the sight's and the odometry's, the scans' is next; past all, none.
  EXPECT_DOUBLE_EQ(gate.NextExpiry(10.2), 10.02 + o.laser_timeout_s);
  EXPECT_TRUE(std::isinf(gate.NextExpiry(11.0)));
}

}  // namespace
}  // namespace corridor::nav
