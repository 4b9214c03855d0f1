// The Hokuyo driver against an emulated scanner (testing/emulators/hokuyo_emulator.h) on a pseudo-terminal (a USB URG)
// and on a local TCP port (a UST on Ethernet): real I/O on real threads, since the transport is the point; every wait
// is for a condition, with a deadline.
#include "drivers/hokuyo/hokuyo_laser.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>

#include "testing/emulators/hokuyo_emulator.h"
#include "testing/eventually.h"
#include "testing/pumping.h"

namespace corridor::drivers::hokuyo {
namespace {

using corridor::testing::Eventually;
using corridor::testing::HokuyoEmulator;
using corridor::testing::HokuyoEmulatorOptions;
using corridor::testing::Pumping;
using namespace std::chrono_literals;

std::string Link(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("corridor_hokuyo_" + name + "_" + std::to_string(::getpid())))
      .string();
}

HokuyoOptions OptionsFor(const std::string& port) {
  HokuyoOptions options;
  options.port = port;
  options.reconnect_s = 0.1;
  return options;
}

// The newest scan a driver handed on.
struct LatestScan {
  std::mutex mutex;
  std::shared_ptr<const LaserScan> scan;
  void Connect(HokuyoLaser& laser) {
    laser.SetScanHandler([this](std::shared_ptr<const LaserScan> s) {
      std::lock_guard lock(mutex);
      scan = std::move(s);
    });
  }
  std::shared_ptr<const LaserScan> Get() {
    std::lock_guard lock(mutex);
    return scan;
  }
};

TEST(HokuyoLaserTest, AUrgOnSerialScansCounterClockwiseFromItsFrontWithErrorsAsNothing) {
  const std::string link = Link("urg");
  HokuyoEmulatorOptions emulated;
  // 1 m plus the angle, so that each beam says where it points; nothing seen beyond 2 rad (its error code 1).
  emulated.range = [](double angle) { return angle > 2.0 ? 0.0 : 1.0 + angle; };
  HokuyoEmulator device(link, emulated);
  SteadyClock clock;
  HokuyoLaser laser(OptionsFor(link), clock);
  LatestScan latest;
  latest.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return laser.status().scans >= 3; }, 3000ms)) << laser.status().last_error;
  const HokuyoStatus status = laser.status();
  EXPECT_EQ(status.state, LinkState::kRunning);
  ASSERT_TRUE(status.parameters);
  EXPECT_EQ(status.parameters->front_step, 384);
  EXPECT_TRUE(device.laser_on());
  const std::shared_ptr<const LaserScan> scan = latest.Get();
  ASSERT_EQ(scan->ranges.size(), 725u - 44u + 1u);
  EXPECT_NEAR(scan->angle_min_rad, (44 - 384) * 2.0 * std::numbers::pi / 1024, 1e-9);
  EXPECT_NEAR(scan->angle_increment_rad, 2.0 * std::numbers::pi / 1024, 1e-12);
  EXPECT_DOUBLE_EQ(scan->range_max_m, 5.6);
  int errors = 0;
  for (std::size_t i = 0; i < scan->ranges.size(); ++i) {
    const double angle = scan->angle_min_rad + i * scan->angle_increment_rad;
    if (angle > 2.0) {
      errors += std::isinf(scan->ranges[i]) ? 1 : 0;
    } else if (1.0 + angle >= 0.02) {
      EXPECT_NEAR(scan->ranges[i], 1.0 + angle, 0.0011) << i;
    }
  }
  EXPECT_GT(errors, 10);
}

TEST(HokuyoLaserTest, AUstOnTcpScansAtFortyHertz) {
  HokuyoEmulatorOptions emulated;
  emulated.model = corridor::testing::Ust10lx();
  HokuyoEmulator device(emulated);
  SteadyClock clock;
  HokuyoLaser laser(OptionsFor("127.0.0.1:" + std::to_string(device.port())), clock);
  LatestScan latest;
  latest.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return laser.status().scans >= 5; }, 3000ms)) << laser.status().last_error;
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t scans = laser.status().scans;
  ASSERT_TRUE(Eventually([&] { return laser.status().scans >= scans + 20; }, 3000ms));
  const double hz = 20.0 / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(hz, 30.0);
  EXPECT_EQ(latest.Get()->ranges.size(), 1081u);
  EXPECT_NEAR(latest.Get()->angle_min_rad, -0.75 * std::numbers::pi, 1e-9);
  // The connection dropped (the device's cable pulled) and back.
  device.Unplug();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kDisconnected; }, 3000ms));
  device.Replug();
  const std::uint64_t before = laser.status().scans;
  ASSERT_TRUE(Eventually([&] { return laser.status().scans > before + 3; }, 3000ms)) << laser.status().last_error;
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

// Pumped by the daemon's control loop every 20 ms (linked_device.h): the connection's bytes are read without waiting,
// the scans (two a tick at 40 Hz) handed on from the pumping thread, and a dropped connection taken up again.
TEST(HokuyoLaserTest, AUstOnTcpPumpedHandsItsScansOnFromThePumpingThread) {
  HokuyoEmulatorOptions emulated;
  emulated.model = corridor::testing::Ust10lx();
  HokuyoEmulator device(emulated);
  SteadyClock clock;
  HokuyoLaser laser(OptionsFor("127.0.0.1:" + std::to_string(device.port())), clock);
  std::atomic<std::thread::id> taker;
  std::atomic<int> scans = 0;
  laser.SetScanHandler([&](std::shared_ptr<const LaserScan> scan) {
    taker = std::this_thread::get_id();
    if (scan->ranges.size() == 1081u) ++scans;
  });
  Pumping pump(laser);
  ASSERT_TRUE(Eventually([&] { return scans >= 5 && taker.load() == pump.id(); }, 3000ms)) << laser.status().last_error;
  const auto start = std::chrono::steady_clock::now();
  const int before = scans;
  ASSERT_TRUE(Eventually([&] { return scans >= before + 20; }, 3000ms));
  EXPECT_GT(20.0 / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
  device.Unplug();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kDisconnected; }, 3000ms));
  device.Replug();
  const int again = scans;
  ASSERT_TRUE(Eventually([&] { return scans > again + 3; }, 3000ms)) << laser.status().last_error;
  EXPECT_EQ(taker.load(), pump.id());
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

TEST(HokuyoLaserTest, NoiseABadCheckCharacterAndALostByteCostAScanNotTheStream) {
  const std::string link = Link("noise");
  HokuyoEmulator device(link, HokuyoEmulatorOptions{});
  SteadyClock clock;
  HokuyoLaser laser(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return laser.status().scans >= 3; }, 3000ms)) << laser.status().last_error;
  device.Noise("\x13\xff garbage\n");
  device.BadCheck();
  ASSERT_TRUE(Eventually([&] { return laser.status().dropped_answers >= 1; }, 2000ms));
  device.DropByte();
  const std::uint64_t dropped = laser.status().dropped_answers;
  ASSERT_TRUE(Eventually([&] { return laser.status().dropped_answers > dropped; }, 2000ms));
  const std::uint64_t scans = laser.status().scans;
  ASSERT_TRUE(Eventually([&] { return laser.status().scans >= scans + 3; }, 2000ms));
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

TEST(HokuyoLaserTest, SilentOrUnpluggedItSaysSoAndScansAgainWhenTheDeviceIsBack) {
  const std::string link = Link("unplug");
  HokuyoEmulator device(link, HokuyoEmulatorOptions{});
  SteadyClock clock;
  std::vector<LinkState> states;
  std::mutex mutex;
  {
    HokuyoLaser laser(OptionsFor(link), clock);
    laser.SetLinkHandler([&](const LinkStatus& s) {
      std::lock_guard lock(mutex);
      states.push_back(s.state);
    });
    ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kRunning; }, 3000ms));
    device.Silence();
    ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kSilent; }, 2000ms));
    {
      std::lock_guard lock(mutex);
      EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end()) << "stale before silent";
    }
    device.Resume();
    ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kRunning; }, 3000ms));
    device.Unplug();
    ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kDisconnected; }, 3000ms));
    device.Replug();  // powered up anew: laser off, not streaming
    const std::uint64_t scans = laser.status().scans;
    ASSERT_TRUE(Eventually([&] { return laser.status().scans > scans + 2; }, 3000ms)) << laser.status().last_error;
    EXPECT_GT(laser.status().reconnects, 0u);
  }
  // The driver gone: the stream and the laser are off.
  EXPECT_TRUE(Eventually([&] { return !device.laser_on(); }, 2000ms));
}

TEST(HokuyoLaserTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(HokuyoLaser(HokuyoOptions{}, clock), std::invalid_argument);
  HokuyoOptions options = OptionsFor("/dev/null");
  options.max_range_m = 0.0;
  EXPECT_THROW(HokuyoLaser(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::hokuyo
