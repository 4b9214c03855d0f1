// The Kobuki driver against the emulated robot on a pseudo-terminal (testing/emulators/kobuki_emulator.h): real serial
// I/O on real threads, since the transport is the point; every wait is for a condition, with a deadline.
#include "drivers/kobuki/kobuki_base.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <string>

#include "testing/emulators/kobuki_emulator.h"
#include "testing/eventually.h"
#include "testing/latest_reports.h"

namespace corridor::drivers::kobuki {
namespace {

using corridor::testing::Eventually;
using corridor::testing::KobukiEmulator;
using corridor::testing::LatestReports;
using namespace std::chrono_literals;

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_kobuki_" + name + "_" + std::to_string(::getpid()));
}

KobukiOptions OptionsFor(const std::filesystem::path& port, double command_timeout_s = 10.0) {
  KobukiOptions options;
  options.port = port;
  options.command_timeout_s = command_timeout_s;
  options.reconnect_s = 0.1;
  return options;
}

bool Near(std::pair<double, double> wheels, double left, double right) {
  return std::abs(wheels.first - left) < 0.002 && std::abs(wheels.second - right) < 0.002;
}

TEST(KobukiBaseTest, ItDrivesTheWheelsItIsToldToAndItsOdometryFollowsThem) {
  const std::filesystem::path link = Link("drive");
  KobukiEmulator robot(link);
  SteadyClock clock;
  KobukiBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << base.status().last_error;
  // Forward at 0.2 m/s (the encoders wrap at 65535 on the way: the emulator starts them near it).
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.2, 0.2); }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.3; }, 5000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.2, 0.0, 0.03)) << latest.Odometry().velocity.linear_mps;
  const WheelOdometry o = latest.Odometry();
  EXPECT_NEAR(o.odom_T_base.y_m, 0.0, 0.01);
  EXPECT_NEAR(o.odom_T_base.yaw_rad, 0.0, 0.02);
  // Turning on the spot at 1 rad/s: each wheel at 115 mm/s.
  base.SetVelocity({0.0, 1.0});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), -0.115, 0.115); }, 2000ms))
      << robot.wheels_mps().first << ", " << robot.wheels_mps().second;
  const double yaw0 = latest.Odometry().odom_T_base.yaw_rad;
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.yaw_rad > yaw0 + 0.5; }, 3000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.0, 1.0, 0.1)) << latest.Odometry().velocity.angular_rps;
  // An arc: forward and turning at once.
  base.SetVelocity({0.2, 0.5});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.1425, 0.2575); }, 2000ms))
      << robot.wheels_mps().first << ", " << robot.wheels_mps().second;
  EXPECT_EQ(base.status().dropped_packets, 0u);
}

TEST(KobukiBaseTest, WhenCommandsStopComingTheWheelsStop) {
  const std::filesystem::path link = Link("timeout");
  KobukiEmulator robot(link);
  SteadyClock clock;
  KobukiBase base(OptionsFor(link, 0.2), clock);
  base.SetVelocity({0.3, 0.0});
  // Well under way first (on the way up the wheels pass near zero too), then stopped once commands stop.
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mps().first > 0.1; }, 3000ms));
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.0, 0.0); }, 2000ms));
}

TEST(KobukiBaseTest, ACliffOrADroppedWheelStopsTheWheelsUntilTheFloorIsBack) {
  const std::filesystem::path link = Link("cliff");
  KobukiEmulator robot(link);
  SteadyClock clock;
  KobukiBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.2, 0.2); }, 3000ms));
  robot.SetCliff(true);
  ASSERT_TRUE(Eventually([&] { return base.status().cliff && Near(robot.wheels_mps(), 0.0, 0.0); }, 2000ms));
  EXPECT_TRUE(latest.Odometry().cliff);
  robot.SetCliff(false);
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.2, 0.2); }, 3000ms));
  robot.SetWheelDrop(true);
  ASSERT_TRUE(Eventually([&] { return base.status().wheel_drop && Near(robot.wheels_mps(), 0.0, 0.0); }, 2000ms));
}

TEST(KobukiBaseTest, TheBumperAndTheBatteryAreReported) {
  const std::filesystem::path link = Link("sensors");
  KobukiEmulator robot(link);
  robot.SetBattery(14.9, 6);  // half way between empty and full, charging on the dock
  SteadyClock clock;
  KobukiBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  // The emulator streams from its start: packets it sent before SetBattery may still wait in the terminal's buffer.
  ASSERT_TRUE(
      Eventually([&] { return latest.Battery() && std::abs(latest.Battery()->voltage_v - 14.9) < 1e-9; }, 3000ms));
  const BatteryState battery = *latest.Battery();
  EXPECT_NEAR(battery.charge, 0.5, 0.02);
  EXPECT_NEAR(battery.voltage_v, 14.9, 1e-9);
  EXPECT_TRUE(battery.on_charger);
  EXPECT_TRUE(battery.charging);
  EXPECT_FALSE(latest.Odometry().bumper_pressed);
  robot.SetBump(true);
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().bumper_pressed; }, 2000ms));
}

TEST(KobukiBaseTest, NoiseAndABadChecksumCostOnePacketNotTheStream) {
  const std::filesystem::path link = Link("noise");
  KobukiEmulator robot(link);
  SteadyClock clock;
  KobukiBase base(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return base.status().packets >= 5; }, 3000ms)) << base.status().last_error;
  robot.Noise({0xAA, 0x55, 0xFF, 0x00, 0x13, 0xAA});
  robot.BadChecksum();
  ASSERT_TRUE(Eventually([&] { return base.status().dropped_packets >= 1; }, 2000ms));
  const std::uint64_t packets = base.status().packets;
  ASSERT_TRUE(Eventually([&] { return base.status().packets >= packets + 5; }, 2000ms));
  EXPECT_EQ(base.status().state, LinkState::kRunning);
}

TEST(KobukiBaseTest, UnpluggedOrSilentItSaysSoStopsTheWheelsAndDrivesAgainWhenTheRobotIsBack) {
  const std::filesystem::path link = Link("unplug");
  KobukiEmulator robot(link);
  SteadyClock clock;
  KobukiBase base(OptionsFor(link), clock);
  std::vector<LinkState> states;
  std::mutex mutex;
  base.SetLinkHandler([&](const LinkStatus& s) {
    std::lock_guard lock(mutex);
    states.push_back(s.state);
  });
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.2, 0.2); }, 3000ms));
  robot.Silence();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kSilent; }, 2000ms));
  {
    std::lock_guard lock(mutex);
    EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end()) << "stale before silent";
  }
  robot.Resume();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  robot.Unplug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kDisconnected; }, 3000ms));
  robot.Replug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(base.status().state) << " " << base.status().last_error;
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(robot.wheels_mps(), 0.1, 0.1); }, 2000ms));
  EXPECT_GT(base.status().reconnects, 0u);
}

TEST(KobukiBaseTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(KobukiBase(KobukiOptions{}, clock), std::invalid_argument);
  KobukiOptions options = OptionsFor("/dev/null");
  options.wheels.track_m = 0.0;
  EXPECT_THROW(KobukiBase(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::kobuki
