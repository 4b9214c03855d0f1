#include "server/nodes/control_node.h"

#include <gtest/gtest.h>

namespace corridor::server {
namespace {

using drivers::FromSeconds;

TEST(DecideCommandTest, TeleopIsAppliedWithinTheDeadmanAndClamped) {
  SafetyOptions o;
  const TeleopCommand teleop{{2.0, -0.5}, FromSeconds(10.0), "rest"};
  const BaseCommand c = DecideCommand({FromSeconds(10.2), &teleop, FromSeconds(10.19)}, o);
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
  const BaseCommand m = DecideCommand({FromSeconds(10.1), nullptr, FromSeconds(10.1), &mission}, o);
  EXPECT_EQ(m.mode, "mission");
  EXPECT_DOUBLE_EQ(m.twist.linear_mps, 0.4);
  EXPECT_EQ(DecideCommand({FromSeconds(10.5), nullptr, FromSeconds(10.5), &mission}, o).mode, "idle");
  const MissionCommand over{FromSeconds(10.0), {}, false};
  EXPECT_EQ(DecideCommand({FromSeconds(10.05), nullptr, FromSeconds(10.05), &over}, o).mode, "idle");
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

}  // namespace
}  // namespace corridor::server
