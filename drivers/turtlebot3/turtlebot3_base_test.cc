// The TurtleBot 3 driver against an emulated OpenCR board on a pseudo-terminal (testing/emulators/opencr_emulator.h):
// real serial I/O on real threads, since the transport is the point; every wait is for a condition, with a deadline.
#include "drivers/turtlebot3/turtlebot3_base.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "testing/emulators/opencr_emulator.h"
#include "testing/eventually.h"
#include "testing/latest_reports.h"

namespace corridor::drivers::turtlebot3 {
namespace {

using corridor::testing::Eventually;
using corridor::testing::LatestReports;
using corridor::testing::OpenCrEmulator;
using namespace std::chrono_literals;

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_opencr_" + name + "_" + std::to_string(::getpid()));
}

TurtleBot3Options OptionsFor(const std::filesystem::path& port, double command_timeout_s = 10.0) {
  TurtleBot3Options options;
  options.port = port;
  options.command_timeout_s = command_timeout_s;
  options.reconnect_s = 0.1;
  return options;
}

// The board takes velocities in hundredths.
bool Near(std::pair<double, double> wheels, double left, double right) {
  return std::abs(wheels.first - left) < 0.002 && std::abs(wheels.second - right) < 0.002;
}

TEST(TurtleBot3BaseTest, ItTurnsTheTorqueOnDrivesTheWheelsAndItsOdometryFollowsThem) {
  const std::filesystem::path link = Link("drive");
  OpenCrEmulator board(link);
  SteadyClock clock;
  TurtleBot3Base base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << base.status().last_error;
  EXPECT_TRUE(board.torque());
  EXPECT_EQ(base.status().model_number, 0x5000);
  // Forward at 0.2 m/s (the int32 positions wrap on the way: the board starts them near it).
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.3; }, 5000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.2, 0.0, 0.03)) << latest.Odometry().velocity.linear_mps;
  const WheelOdometry o = latest.Odometry();
  EXPECT_NEAR(o.odom_T_base.y_m, 0.0, 0.01);
  EXPECT_NEAR(o.odom_T_base.yaw_rad, 0.0, 0.02);
  // Turning on the spot at 1 rad/s: each wheel at 80 mm/s.
  base.SetVelocity({0.0, 1.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), -0.08, 0.08); }, 2000ms))
      << board.wheels_mps().first << ", " << board.wheels_mps().second;
  const double yaw0 = latest.Odometry().odom_T_base.yaw_rad;
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.yaw_rad > yaw0 + 0.5; }, 3000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.0, 1.0, 0.1)) << latest.Odometry().velocity.angular_rps;
  EXPECT_GT(board.heartbeats(), 0);
  EXPECT_EQ(base.status().dropped_packets, 0u);
  EXPECT_EQ(base.status().device_errors, 0u);
  EXPECT_EQ(board.crc_errors(), 0);
}

TEST(TurtleBot3BaseTest, WhenCommandsStopComingTheWheelsStop) {
  const std::filesystem::path link = Link("timeout");
  OpenCrEmulator board(link);
  SteadyClock clock;
  TurtleBot3Base base(OptionsFor(link, 0.3), clock);
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return board.wheels_mps().first > 0.1; }, 3000ms));
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.0, 0.0); }, 2000ms));
}

TEST(TurtleBot3BaseTest, TheBumperAndTheBatteryAreReported) {
  const std::filesystem::path link = Link("sensors");
  OpenCrEmulator board(link);
  board.SetBattery(11.5, 62.5);
  SteadyClock clock;
  TurtleBot3Base base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return latest.Battery().has_value(); }, 3000ms));
  EXPECT_NEAR(latest.Battery()->voltage_v, 11.5, 1e-9);
  EXPECT_NEAR(latest.Battery()->charge, 0.625, 1e-9);
  EXPECT_FALSE(latest.Odometry().bumper_pressed);
  board.SetBumper(true);
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().bumper_pressed && base.status().bumper; }, 2000ms));
}

TEST(TurtleBot3BaseTest, NoiseABadCrcAndASlowBoardCostAReadNotTheLink) {
  const std::filesystem::path link = Link("noise");
  OpenCrEmulator board(link);
  SteadyClock clock;
  TurtleBot3Base base(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return base.status().reads >= 5; }, 3000ms)) << base.status().last_error;
  board.Noise({0xFF, 0xFF, 0xFD, 0x00, 0xC8, 0xFF, 0x7F, 0x13});  // a header whose length is absurd
  board.BadCrc();
  ASSERT_TRUE(Eventually([&] { return base.status().dropped_packets >= 1; }, 2000ms));
  std::uint64_t reads = base.status().reads;
  ASSERT_TRUE(Eventually([&] { return base.status().reads >= reads + 5; }, 2000ms));
  // Answers 30 ms late (later than a cycle): the reads come late, the wheels are still driven.
  board.Slow(0.03);
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.1, 0.1); }, 3000ms));
  EXPECT_EQ(base.status().state, LinkState::kRunning);
}

TEST(TurtleBot3BaseTest, UnpluggedOrSilentItSaysSoStopsAndDrivesAgainWhenTheBoardIsBack) {
  const std::filesystem::path link = Link("unplug");
  OpenCrEmulator board(link);
  SteadyClock clock;
  TurtleBot3Base base(OptionsFor(link), clock);
  std::vector<LinkState> states;
  std::mutex mutex;
  base.SetLinkHandler([&](const LinkStatus& s) {
    std::lock_guard lock(mutex);
    states.push_back(s.state);
  });
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 3000ms));
  board.Silence();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kSilent; }, 2000ms));
  {
    std::lock_guard lock(mutex);
    EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end()) << "stale before silent";
  }
  board.Resume();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  board.Unplug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kDisconnected; }, 3000ms));
  board.Replug();  // restarted: torque off until the driver turns it on again
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(base.status().state) << " " << base.status().last_error;
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.1, 0.1); }, 2000ms));
  EXPECT_TRUE(board.torque());
  EXPECT_GT(base.status().reconnects, 0u);
}

TEST(TurtleBot3BaseTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(TurtleBot3Base(TurtleBot3Options{}, clock), std::invalid_argument);
  TurtleBot3Options options = OptionsFor("/dev/null");
  options.poll_period_s = 0.0;
  EXPECT_THROW(TurtleBot3Base(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::turtlebot3
