// The RPLIDAR driver against the emulated device on a pseudo-terminal (testing/emulators/rplidar_emulator.h): real
// serial I/O on real threads, since the transport is the point; every wait is for a condition, with a deadline.
#include "drivers/rplidar/rplidar_laser.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <numbers>
#include <string>

#include "testing/emulators/rplidar_emulator.h"
#include "testing/eventually.h"
#include "testing/room_scans.h"

namespace corridor::drivers::rplidar {
namespace {

using corridor::testing::Eventually;
using corridor::testing::RoomScans;
using corridor::testing::RplidarEmulator;
using corridor::testing::RplidarEmulatorOptions;
using namespace std::chrono_literals;

// A room where the robot's right (90 degrees clockwise in the device) is a wall 1 m away, everything else 3 m. Its
// edges lie half-way between beams, so that express samples (whole degrees less a correction of under half a degree)
// fall on the same side as their beam.
double Room(double angle_cw_deg) { return std::abs(angle_cw_deg - 90.0) < 4.5 ? 1.0 : 3.0; }

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_rplidar_" + name + "_" + std::to_string(::getpid()));
}

RplidarOptions OptionsFor(const std::filesystem::path& port) {
  RplidarOptions options;
  options.port = port;
  options.silence_s = 0.3;
  options.reconnect_s = 0.1;
  return options;
}

TEST(RplidarLaserTest, ScansArriveCounterClockwiseFromForwardWithTheDevicesInformation) {
  const std::filesystem::path link = Link("scan");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room});
  SteadyClock clock;
  RplidarLaser laser(OptionsFor(link), clock);
  RoomScans received(Room);
  std::shared_ptr<const LaserScan> last;
  std::mutex last_mutex;
  laser.SetScanHandler([&](std::shared_ptr<const LaserScan> scan) {
    received.Take(*scan);
    std::lock_guard lock(last_mutex);
    last = std::move(scan);
  });
  ASSERT_TRUE(Eventually([&] { return received.count() >= 3; }, 5000ms)) << laser.status().last_error;
  EXPECT_EQ(received.wrong(), 0);
  const RplidarStatus status = laser.status();
  EXPECT_EQ(status.state, LinkState::kRunning);
  ASSERT_TRUE(status.info);
  EXPECT_EQ(status.info->model, 0x18);
  EXPECT_EQ(status.info->firmware_major, 1);
  // The wall on the right is at -90 degrees in the scan.
  std::lock_guard lock(last_mutex);
  const auto beam =
      static_cast<std::size_t>(std::lround((-std::numbers::pi / 2 - last->angle_min_rad) / last->angle_increment_rad));
  EXPECT_NEAR(last->ranges[beam], 1.0, 1e-3);
}

TEST(RplidarLaserTest, NoiseABadCheckBitAndALostByteCostAFewMeasurementsNotTheScans) {
  const std::filesystem::path link = Link("faults");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room});
  SteadyClock clock;
  RplidarLaser laser(OptionsFor(link), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Noise({0x00, 0xFF, 0xA5, 0x13, 0x37});
  ASSERT_TRUE(Eventually([&] { return received.count() >= 4; }, 3000ms));
  device.BadCheckBit();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 6; }, 3000ms));
  device.DropByte();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 8; }, 3000ms));
  EXPECT_EQ(received.wrong(), 0) << "a beam from a misread node";
  EXPECT_GT(laser.status().skipped_bytes, 0u);
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

TEST(RplidarLaserTest, InExpressModeScansArriveAndAFaultCostsOnlyTheCapsulesItTouches) {
  const std::filesystem::path link = Link("express");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room});
  SteadyClock clock;
  RplidarOptions options = OptionsFor(link);
  options.scan_mode = ScanMode::kExpress;
  RplidarLaser laser(options, clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  EXPECT_EQ(device.express_scans_started(), 1);
  EXPECT_EQ(device.scans_started(), 0);
  device.Noise({0x00, 0xA5, 0x5A, 0x13, 0x37});
  ASSERT_TRUE(Eventually([&] { return received.count() >= 4; }, 3000ms));
  device.BadCheckBit();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 6; }, 3000ms));
  device.DropByte();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 8; }, 3000ms));
  EXPECT_EQ(received.wrong(), 0) << "a beam from a misread capsule";
  EXPECT_GT(laser.status().skipped_bytes, 0u);
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

TEST(RplidarLaserTest, UnpluggedItSaysSoAndScansAgainOncePluggedBackIn) {
  const std::filesystem::path link = Link("unplug");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room});
  SteadyClock clock;
  RplidarLaser laser(OptionsFor(link), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Unplug();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kDisconnected; }, 3000ms))
      << ToString(laser.status().state);
  EXPECT_FALSE(laser.status().last_error.empty());
  const int before = received.count();
  device.Replug();
  ASSERT_TRUE(Eventually([&] { return received.count() >= before + 2; }, 5000ms)) << laser.status().last_error;
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
  EXPECT_GT(laser.status().reconnects, 0u);
  EXPECT_EQ(received.wrong(), 0);
}

TEST(RplidarLaserTest, ADeviceThatFallsSilentIsCalledSilentAndScansAgainWhenItAnswers) {
  const std::filesystem::path link = Link("silent");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room});
  SteadyClock clock;
  RplidarLaser laser(OptionsFor(link), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Silence();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kSilent; }, 3000ms));
  const int before = received.count();
  device.Resume();
  ASSERT_TRUE(Eventually([&] { return received.count() >= before + 2; }, 5000ms)) << laser.status().last_error;
  EXPECT_GE(device.scans_started(), 2);
}

TEST(RplidarLaserTest, ADeviceReportingAnErrorIsResetAndThenScans) {
  const std::filesystem::path link = Link("error");
  RplidarEmulator device(link, RplidarEmulatorOptions{.range = Room, .health_status = 2});
  SteadyClock clock;
  RplidarLaser laser(OptionsFor(link), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  EXPECT_EQ(device.resets(), 1);
  EXPECT_EQ(received.wrong(), 0);
}

TEST(RplidarLaserTest, ANamelessPortOrBadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(RplidarLaser(RplidarOptions{}, clock), std::invalid_argument);
  RplidarOptions options = OptionsFor("/dev/null");
  options.silence_s = 0.0;
  EXPECT_THROW(RplidarLaser(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::rplidar
