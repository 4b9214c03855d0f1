#include "server/nodes/control_node.h"

#include <gtest/gtest.h>

#include <mutex>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// Four lanes, each clear.
GroundLanes ClearLanes() {
  GroundLanes g;
  for (double offset : {0.15, 0.05, -0.05, -0.15}) {
    nav::LaneResult lane;
    lane.offset_m = offset;
    lane.free_distance_m = 4.0;
    g.lanes.push_back(lane);
  }
  return g;
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

// The control node on the simulated clock: each step is 20 ms with fresh odometry and clear lanes.
class ControlNodeTest : public ::testing::Test {
 protected:
  ControlNodeTest() : executors_(clock_, Schedule::kLockstep), node_(executors_.control, bus_, base_, {}) {
    node_.Activate();
  }

  // One step of `seconds` at which the base reports `pressed` and teleop asks for `linear_mps`; returns what was sent.
  BaseCommand Drive(double linear_mps, bool pressed = false, double seconds = 0.02) {
    clock_.Set(clock_.Now() + drivers::FromSeconds(seconds));
    bus_.Get(topics::kOdometry).Publish(drivers::WheelOdometry{clock_.Now(), {}, {}, pressed});
    bus_.Get(topics::kGroundLanes).Publish(ClearLanes());
    bus_.Get(topics::kTeleop).Publish(TeleopCommand{{linear_mps, 0.0}, clock_.Now(), "test"});
    executors_.RunUntilIdle();
    clock_.Set(clock_.Now() + drivers::FromSeconds(0.02));  // the tick decides on them
    executors_.RunUntilIdle();
    const auto sent = bus_.Get(topics::kCmdVel).latest();
    return sent ? *sent : BaseCommand{};
  }

  drivers::ManualClock clock_;
  Executors executors_;
  Bus bus_;
  RecordingBase base_;
  ControlNode node_;
};

TEST_F(ControlNodeTest, EachBumpIsPublishedWithTheWayTheBaseWasDrivingAndHoldsThatWay) {
  ASSERT_DOUBLE_EQ(Drive(-0.1).twist.linear_mps, -0.1);
  Drive(-0.1, true);
  const auto backing = bus_.Get(topics::kBumped).latest();
  ASSERT_NE(backing, nullptr);
  EXPECT_TRUE(backing->backing);
  // Backing on into it is held; driving away forward is not.
  const BaseCommand held = Drive(-0.1);
  EXPECT_EQ(held.twist.linear_mps, 0.0);
  EXPECT_EQ(held.reason, nav::GateReason::kBumpedBacking);
  EXPECT_EQ(base_.last().linear_mps, 0.0);
  ASSERT_DOUBLE_EQ(Drive(0.2).twist.linear_mps, 0.2);

  Drive(0.2, true);
  const auto forward = bus_.Get(topics::kBumped).latest();
  ASSERT_NE(forward, nullptr);
  EXPECT_GT(forward->stamp_ns, backing->stamp_ns);
  EXPECT_FALSE(forward->backing);
  EXPECT_EQ(Drive(0.2).reason, nav::GateReason::kBumpedForward);

  node_.Deactivate();
  EXPECT_EQ(base_.last().linear_mps, 0.0);
  EXPECT_EQ(bus_.Get(topics::kCmdVel).latest()->reason, nav::GateReason::kShuttingDown);
}

TEST_F(ControlNodeTest, AFaultAnywhereStopsTheRobotForTheHoldAndSaysWhatFailed) {
  ASSERT_DOUBLE_EQ(Drive(0.3).twist.linear_mps, 0.3);
  bus_.Get(topics::kFaults).Publish(Fault{clock_.Now(), "mission", "frame", "vector::at"});
  executors_.RunUntilIdle();
  EXPECT_EQ(base_.last().linear_mps, 0.0) << "stopped at once, not at the next tick";
  const BaseCommand stopped = Drive(0.3);
  EXPECT_EQ(stopped.mode, nav::ControlMode::kStopped);
  EXPECT_EQ(StopReason(stopped), "protective stop: mission failed: vector::at");
  EXPECT_EQ(node_.Status()["health"], "degraded");
  // After the hold it drives again.
  Drive(0.3, false, nav::CommandGateOptions{}.fault_hold_s);
  EXPECT_DOUBLE_EQ(Drive(0.3).twist.linear_mps, 0.3);
  EXPECT_EQ(node_.Status()["health"], "ok");
}

}  // namespace
}  // namespace corridor::server
