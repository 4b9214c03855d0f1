#include "server/nodes/control_node.h"

#include <gtest/gtest.h>

#include <mutex>

#include "server/runtime/topics.h"
#include "testing/eventually.h"

namespace corridor::server {
namespace {

using drivers::FromSeconds;
using testing::Eventually;

// Four lanes, each blocked at `dead_end_m` (or clear when negative).
GroundLanes LanesAt(double dead_end_m) {
  GroundLanes g;
  for (double offset : {0.15, 0.05, -0.05, -0.15}) {
    nav::LaneResult lane;
    lane.offset_m = offset;
    lane.dead_end = dead_end_m >= 0.0;
    lane.free_distance_m = dead_end_m >= 0.0 ? dead_end_m : 4.0;
    g.lanes.push_back(lane);
  }
  return g;
}
const GroundLanes kClear = LanesAt(-1.0);

TEST(DecideCommandTest, TeleopIsAppliedWithinTheDeadmanAndClamped) {
  SafetyOptions o;
  const TeleopCommand teleop{{2.0, -0.5}, FromSeconds(10.0), "rest"};
  const BaseCommand c = DecideCommand({FromSeconds(10.2), &teleop, FromSeconds(10.19), nullptr, &kClear, FromSeconds(10.19)}, o);
  EXPECT_EQ(c.mode, "teleop");
  EXPECT_DOUBLE_EQ(c.twist.linear_mps, o.max_linear_mps);
  EXPECT_DOUBLE_EQ(c.twist.angular_rps, -0.5);
}

TEST(DecideCommandTest, DeadmanLapsesAndTheRobotStops) {
  SafetyOptions o;
  const TeleopCommand teleop{{0.3, 0.0}, FromSeconds(10.0), "rest"};
  const BaseCommand c = DecideCommand({FromSeconds(10.0 + o.teleop_deadman_s + 0.01), &teleop, FromSeconds(10.5)}, o);
  EXPECT_EQ(c.mode, "idle");
  EXPECT_EQ(c.twist.linear_mps, 0.0);
  EXPECT_EQ(c.twist.angular_rps, 0.0);
}

TEST(DecideCommandTest, TeleopOverridesAMissionAndAStaleMissionIsIgnored) {
  SafetyOptions o;
  const TeleopCommand teleop{{0.1, 0.0}, FromSeconds(10.0), "rest"};
  const MissionCommand mission{FromSeconds(10.0), {0.4, 0.2}};
  EXPECT_EQ(DecideCommand({FromSeconds(10.1), &teleop, FromSeconds(10.1), &mission}, o).mode, "teleop");
  const BaseCommand m = DecideCommand({FromSeconds(10.1), nullptr, FromSeconds(10.1), &mission, &kClear, FromSeconds(10.1)}, o);
  EXPECT_EQ(m.mode, "mission");
  EXPECT_DOUBLE_EQ(m.twist.linear_mps, 0.4);
  EXPECT_EQ(DecideCommand({FromSeconds(10.5), nullptr, FromSeconds(10.5), &mission}, o).mode, "idle");
  const MissionCommand over{FromSeconds(10.0), {}, false};
  EXPECT_EQ(DecideCommand({FromSeconds(10.05), nullptr, FromSeconds(10.05), &over}, o).mode, "idle");
}

TEST(DecideCommandTest, ForwardSpeedStopsBeforeWhatTheCameraSeesAndNeedsFreshDepth) {
  SafetyOptions o;
  const TeleopCommand forward{{0.5, 0.0}, FromSeconds(10.0), "rest"};
  const auto at = [&](const GroundLanes* lanes, drivers::TimeNs lanes_ns) {
    return DecideCommand({FromSeconds(10.05), &forward, FromSeconds(10.05), nullptr, lanes, lanes_ns}, o);
  };
  EXPECT_DOUBLE_EQ(at(&kClear, FromSeconds(10.04)).twist.linear_mps, 0.5);
  // A dead-end 0.4 m from the centre is 0.2 m from the front: the speed that stops within it (0.42 m/s).
  const GroundLanes near = LanesAt(0.4);
  const BaseCommand slowed = at(&near, FromSeconds(10.04));
  EXPECT_LT(slowed.twist.linear_mps, 0.5);
  EXPECT_NEAR(nav::StoppingDistance(slowed.twist.linear_mps, o.stopping), 0.2, 1e-9);
  EXPECT_EQ(slowed.reason, "slowed for an obstacle ahead");
  // At the front already: no forward motion at all.
  const GroundLanes touching = LanesAt(0.2);
  EXPECT_EQ(at(&touching, FromSeconds(10.04)).twist.linear_mps, 0.0);
  // No depth frame for longer than depth_timeout_s, or never: hold forward motion; reversing and turning stay allowed.
  EXPECT_EQ(at(&kClear, FromSeconds(10.05 - o.depth_timeout_s - 0.01)).twist.linear_mps, 0.0);
  EXPECT_EQ(at(nullptr, -1).reason, "no depth frames: not driving forward");
  const TeleopCommand back{{-0.3, 0.5}, FromSeconds(10.0), "rest"};
  const BaseCommand reversing = DecideCommand({FromSeconds(10.05), &back, FromSeconds(10.05)}, o);
  EXPECT_DOUBLE_EQ(reversing.twist.linear_mps, -0.3);
  EXPECT_DOUBLE_EQ(reversing.twist.angular_rps, 0.5);
}

TEST(DecideCommandTest, AfterABumpNothingDrivesOnThatWayForASecondButItMayTurnAndDriveAway) {
  SafetyOptions o;
  const MissionCommand push{FromSeconds(10.0), {0.2, 0.3}};
  const auto at = [&](double now_s, const MissionCommand& command, drivers::TimeNs bump_ns, int direction = 1) {
    return DecideCommand({FromSeconds(now_s), nullptr, FromSeconds(now_s), &command, &kClear, FromSeconds(now_s),
                          bump_ns, direction},
                         o);
  };
  const BaseCommand held = at(10.05, push, FromSeconds(10.0));
  EXPECT_EQ(held.mode, "mission");
  EXPECT_EQ(held.twist.linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(held.twist.angular_rps, 0.3);
  EXPECT_EQ(held.reason, "bumper pressed: not driving forward");
  const MissionCommand back{FromSeconds(10.0), {-0.1, 0.0}};
  EXPECT_DOUBLE_EQ(at(10.05, back, FromSeconds(10.0)).twist.linear_mps, -0.1);
  // A second after the bumper let go, forward again; never bumped: forward.
  const MissionCommand later{FromSeconds(11.2), {0.2, 0.3}};
  EXPECT_DOUBLE_EQ(at(11.25, later, FromSeconds(10.0)).twist.linear_mps, 0.2);
  EXPECT_DOUBLE_EQ(at(11.25, later, -1).twist.linear_mps, 0.2);
  // Bumped backing into something: it may drive forward away from it, not back on.
  EXPECT_DOUBLE_EQ(at(10.05, push, FromSeconds(10.0), -1).twist.linear_mps, 0.2);
  const BaseCommand no_back = at(10.05, back, FromSeconds(10.0), -1);
  EXPECT_EQ(no_back.twist.linear_mps, 0.0);
  EXPECT_EQ(no_back.reason, "bumper pressed: not backing");
}

TEST(DecideCommandTest, NoOdometryMeansStopWithAReason) {
  SafetyOptions o;
  const TeleopCommand teleop{{0.3, 0.0}, FromSeconds(10.0), "rest"};
  for (const drivers::TimeNs last : {drivers::TimeNs{-1}, FromSeconds(9.0)}) {
    const BaseCommand c = DecideCommand({FromSeconds(10.1), &teleop, last}, o);
    EXPECT_EQ(c.mode, "stopped");
    EXPECT_EQ(c.twist.linear_mps, 0.0);
    EXPECT_EQ(c.reason, "no odometry from the base");
  }
}

// A base that only remembers the last command it was given: the hardware is not here.
class RecordingBase final : public drivers::DiffDriveBase {
 public:
  drivers::BaseLimits limits() const override { return {0.5, 1.5, 1.0, 3.0, 0.2}; }
  void SetVelocity(const nav::Twist2& command) override {
    const std::lock_guard lock(mutex_);
    last_ = command;
  }
  void SetOdometryHandler(OdometryHandler) override {}
  nav::Twist2 last() const {
    const std::lock_guard lock(mutex_);
    return last_;
  }

 private:
  mutable std::mutex mutex_;
  nav::Twist2 last_;
};

TEST(ControlNodeTest, EachBumpIsPublishedWithTheWayTheBaseWasDrivingAndHoldsThatWay) {
  Executor executor("control");
  Bus bus;
  const drivers::SteadyClock clock;
  RecordingBase base;
  ControlNode node(executor, bus, base, clock, SafetyOptions{});
  executor.Start();
  node.Activate();
  const auto odometry = [&](bool pressed) {
    bus.Get(topics::kOdometry).Publish(drivers::WheelOdometry{clock.Now(), {}, {}, pressed});
  };
  // Teleop at `linear_mps` with fresh odometry and clear lanes; true once the base is sent `expected_mps`.
  const auto drive = [&](double linear_mps, double expected_mps) {
    return Eventually([&] {
      odometry(false);
      bus.Get(topics::kGroundLanes).Publish(LanesAt(-1.0));
      bus.Get(topics::kTeleop).Publish(TeleopCommand{{linear_mps, 0.0}, clock.Now(), "test"});
      const auto sent = bus.Get(topics::kCmdVel).latest();
      return sent && sent->twist.linear_mps == expected_mps && base.last().linear_mps == expected_mps;
    });
  };
  const auto bump = [&](drivers::TimeNs after_ns) {
    odometry(true);
    std::shared_ptr<const Bumped> bumped;
    Eventually([&] {
      bumped = bus.Get(topics::kBumped).latest();
      return bumped && bumped->stamp_ns > after_ns;
    });
    return bumped;
  };

  ASSERT_TRUE(drive(-0.1, -0.1));
  const auto backing = bump(clock.Now() - 1);
  ASSERT_TRUE(backing);
  EXPECT_TRUE(backing->backing);
  // Backing on into it is held; driving away forward is not.
  EXPECT_TRUE(drive(-0.1, 0.0));
  EXPECT_EQ(bus.Get(topics::kCmdVel).latest()->reason, "bumper pressed: not backing");
  ASSERT_TRUE(drive(0.2, 0.2));

  const auto forward = bump(backing->stamp_ns);
  ASSERT_TRUE(forward);
  EXPECT_FALSE(forward->backing);
  EXPECT_TRUE(drive(0.2, 0.0));
  EXPECT_EQ(bus.Get(topics::kCmdVel).latest()->reason, "bumper pressed: not driving forward");

  node.Deactivate();
  executor.Stop();
  EXPECT_EQ(base.last().linear_mps, 0.0);
}

}  // namespace
}  // namespace corridor::server
