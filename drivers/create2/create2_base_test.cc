// The Create 2 driver against the emulated robot on a pseudo-terminal (testing/emulators/create2_emulator.h): real
// serial I/O on real threads, since the transport is the point; every wait is for a condition, with a deadline.
#include "drivers/create2/create2_base.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <thread>

#include "testing/emulators/create2_emulator.h"
#include "testing/eventually.h"
#include "testing/latest_reports.h"
#include "testing/pumping.h"

namespace corridor::drivers::create2 {
namespace {

using corridor::testing::Create2Emulator;
using corridor::testing::Eventually;
using corridor::testing::LatestReports;
using corridor::testing::Pumping;
using namespace std::chrono_literals;

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_create2_" + name + "_" + std::to_string(::getpid()));
}

Create2Options OptionsFor(const std::filesystem::path& port, double command_timeout_s = 10.0) {
  Create2Options options;
  options.port = port;
  options.command_timeout_s = command_timeout_s;
  options.reconnect_s = 0.1;
  return options;
}

TEST(Create2BaseTest, ItDrivesTheWheelsItIsToldToAndItsOdometryFollowsThem) {
  const std::filesystem::path link = Link("drive");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2; }, 3000ms)) << "not in Safe mode: " << robot.mode();
  // Forward at 0.2 m/s (the encoders wrap at 65535 on the way: the emulator starts them near it).
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps() == std::make_pair(200, 200); }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.3; }, 5000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.2, 0.0, 0.03)) << latest.Odometry().velocity.linear_mps;
  WheelOdometry o = latest.Odometry();
  EXPECT_NEAR(o.odom_T_base.y_m, 0.0, 0.01);
  EXPECT_NEAR(o.odom_T_base.yaw_rad, 0.0, 0.02);
  // Turning on the spot at 1 rad/s: the wheels at -+117.5 mm/s.
  base.SetVelocity({0.0, 1.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps() == std::make_pair(-118, 118); }, 2000ms))
      << robot.wheels_mmps().first << ", " << robot.wheels_mmps().second;
  const double yaw0 = latest.Odometry().odom_T_base.yaw_rad;
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.yaw_rad > yaw0 + 0.5; }, 3000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.0, 1.0, 0.1)) << latest.Odometry().velocity.angular_rps;
  EXPECT_EQ(base.status().state, LinkState::kRunning);
  EXPECT_EQ(base.status().dropped_frames, 0u);
}

TEST(Create2BaseTest, WhenCommandsStopComingTheWheelsStop) {
  const std::filesystem::path link = Link("timeout");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link, 0.2), clock);
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2; }, 3000ms));
  base.SetVelocity({0.3, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps().first > 0; }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps() == std::make_pair(0, 0); }, 2000ms));
}

TEST(Create2BaseTest, ACliffStopsTheWheelsAndOnceTheFloorIsBackItDrivesAgain) {
  const std::filesystem::path link = Link("cliff");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2; }, 3000ms));
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps().first == 200; }, 2000ms));
  robot.SetCliff(true);
  ASSERT_TRUE(Eventually([&] { return base.status().cliff; }, 2000ms));
  EXPECT_EQ(robot.wheels_mmps(), std::make_pair(0, 0));
  EXPECT_EQ(robot.mode(), 1) << "Safe mode falls back to Passive on a cliff";
  robot.SetCliff(false);
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2 && robot.wheels_mmps().first == 200; }, 3000ms));
}

TEST(Create2BaseTest, TheBumperAndTheBatteryAreReported) {
  const std::filesystem::path link = Link("sensors");
  Create2Emulator robot(link);
  robot.SetBattery(1348, 2696, true);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return latest.Battery().has_value(); }, 3000ms));
  const BatteryState battery = *latest.Battery();
  EXPECT_NEAR(battery.charge, 0.5, 1e-9);
  EXPECT_NEAR(battery.voltage_v, 14.8, 1e-9);
  EXPECT_TRUE(battery.on_charger);
  EXPECT_TRUE(battery.charging);
  EXPECT_GT(battery.current_a, 0.0);
  EXPECT_FALSE(latest.Odometry().bumper_pressed);
  robot.SetBump(true);
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().bumper_pressed; }, 2000ms));
}

TEST(Create2BaseTest, NoiseAndABadChecksumCostOneFrameNotTheStream) {
  const std::filesystem::path link = Link("noise");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return base.status().frames >= 5; }, 3000ms)) << base.status().last_error;
  robot.Noise({19, 0xFF, 0x00, 0x13, 0x42});
  robot.BadChecksum();
  ASSERT_TRUE(Eventually([&] { return base.status().dropped_frames >= 1; }, 2000ms));
  const std::uint64_t frames = base.status().frames;
  ASSERT_TRUE(Eventually([&] { return base.status().frames >= frames + 5; }, 2000ms));
  EXPECT_EQ(base.status().state, LinkState::kRunning);
}

TEST(Create2BaseTest, UnpluggedOrSilentItSaysSoAndDrivesAgainWhenTheRobotIsBack) {
  const std::filesystem::path link = Link("unplug");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2; }, 3000ms));
  robot.Silence();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kSilent; }, 2000ms));
  robot.Resume();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  robot.Unplug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kDisconnected; }, 3000ms));
  robot.Replug();  // powered up anew: the OI off until the driver starts it
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2 && base.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(base.status().state) << " " << base.status().last_error;
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps().first == 100; }, 2000ms));
  EXPECT_GT(base.status().reconnects, 0u);
}

// The daemon's control loop pumps the driver (linked_device.h): the frames are taken and the wheels written on the
// pumping thread; a robot unplugged under the pumps is taken up again and pumped again; once the pumps stop, the
// driver's own thread takes the stream back.
TEST(Create2BaseTest, PumpedItsStreamRunsOnThePumpersThreadAndItsOwnOnceThePumpsStop) {
  const std::filesystem::path link = Link("pumped");
  Create2Emulator robot(link);
  SteadyClock clock;
  Create2Base base(OptionsFor(link), clock);
  std::atomic<std::thread::id> reporter;
  base.SetOdometryHandler([&](const WheelOdometry&) { reporter = std::this_thread::get_id(); });
  auto pump = std::make_unique<Pumping>(base);
  ASSERT_TRUE(Eventually([&] { return reporter.load() == pump->id(); }, 3000ms));
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps() == std::make_pair(200, 200); }, 2000ms));
  robot.Unplug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kDisconnected; }, 3000ms));
  robot.Replug();
  ASSERT_TRUE(Eventually([&] { return robot.mode() == 2 && base.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(base.status().state) << " " << base.status().last_error;
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps().first == 100; }, 2000ms));
  EXPECT_EQ(reporter.load(), pump->id());
  const std::thread::id pumper = pump->id();
  pump.reset();
  reporter = std::thread::id();
  ASSERT_TRUE(Eventually([&] { return reporter.load() != std::thread::id(); }, 2000ms));
  EXPECT_NE(reporter.load(), pumper);
  base.SetVelocity({0.15, 0.0});
  ASSERT_TRUE(Eventually([&] { return robot.wheels_mmps().first == 150; }, 2000ms));
}

TEST(Create2BaseTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(Create2Base(Create2Options{}, clock), std::invalid_argument);
  Create2Options options = OptionsFor("/dev/null");
  options.wheels.track_m = 0.0;
  EXPECT_THROW(Create2Base(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::create2
