// The TurtleBot 3 laser driver against the emulated LDS-01 and LDS-02 on a pseudo-terminal (testing/emulators/
// lds_emulator.h): real serial I/O on real threads, since the transport is the point; every wait is for a condition,
// with a deadline.
#include "drivers/lds/lds_laser.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <numbers>
#include <string>

#include "testing/emulators/lds_emulator.h"
#include "testing/eventually.h"
#include "testing/room_scans.h"

namespace corridor::drivers::lds {
namespace {

using corridor::testing::Eventually;
using corridor::testing::LdsEmulator;
using corridor::testing::LdsEmulatorOptions;
using corridor::testing::RoomScans;
using namespace std::chrono_literals;

// A room where the robot's right (90 degrees clockwise in the device) is a wall 1 m away, everything else 3 m.
double Room(double angle_cw_deg) { return std::abs(angle_cw_deg - 90.0) < 5.0 ? 1.0 : 3.0; }

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_lds_" + name + "_" + std::to_string(::getpid()));
}

LdsOptions OptionsFor(const std::filesystem::path& port, Model model) {
  LdsOptions options;
  options.model = model;
  options.port = port;
  options.silence_s = 0.3;
  options.reconnect_s = 0.1;
  return options;
}

class LdsLaserTest : public ::testing::TestWithParam<Model> {
 protected:
  bool lds01() const { return GetParam() == Model::kLds01; }
  LdsEmulatorOptions Emulated() const { return {.lds01 = lds01(), .range = Room}; }
};

TEST_P(LdsLaserTest, ScansArriveCounterClockwiseFromForward) {
  const std::filesystem::path link = Link("scan");
  LdsEmulator device(link, Emulated());
  SteadyClock clock;
  RoomScans received(Room);
  std::shared_ptr<const LaserScan> last;
  std::mutex last_mutex;
  {
    LdsLaser laser(OptionsFor(link, GetParam()), clock);
    laser.SetScanHandler([&](std::shared_ptr<const LaserScan> scan) {
      received.Take(*scan);
      std::lock_guard lock(last_mutex);
      last = std::move(scan);
    });
    ASSERT_TRUE(Eventually([&] { return received.count() >= 3; }, 5000ms)) << laser.status().last_error;
    EXPECT_EQ(received.wrong(), 0);
    const LdsStatus status = laser.status();
    EXPECT_EQ(status.state, LinkState::kRunning);
    EXPECT_EQ(status.skipped_bytes, 0u);
    EXPECT_DOUBLE_EQ(status.speed_deg_s, lds01() ? 0.0 : 6.0 * 360.0);
    if (lds01()) {
      EXPECT_EQ(device.starts(), 1);
    }
  }
  // The wall on the right is at -90 degrees in the scan; every degree measured.
  std::lock_guard lock(last_mutex);
  const auto beam =
      static_cast<std::size_t>(std::lround((-std::numbers::pi / 2 - last->angle_min_rad) / last->angle_increment_rad));
  EXPECT_NEAR(last->ranges[beam], 1.0, 1e-3);
  EXPECT_EQ(std::count_if(last->ranges.begin(), last->ranges.end(), [](float r) { return std::isfinite(r); }), 360);
  // Closed: an LDS-01 is told to stop.
  if (lds01()) {
    EXPECT_TRUE(Eventually([&] { return !device.sending(); }, 1000ms));
  }
}

TEST_P(LdsLaserTest, NoiseABadPacketAndALostByteCostAFewMeasurementsNotTheScans) {
  const std::filesystem::path link = Link("faults");
  LdsEmulator device(link, Emulated());
  SteadyClock clock;
  LdsLaser laser(OptionsFor(link, GetParam()), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Noise({0x54, 0x2C, 0xFA, 0xA0, 0x13, 0x37});
  ASSERT_TRUE(Eventually([&] { return received.count() >= 4; }, 3000ms));
  device.Corrupt();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 6; }, 3000ms));
  device.DropByte();
  ASSERT_TRUE(Eventually([&] { return received.count() >= 8; }, 3000ms));
  EXPECT_EQ(received.wrong(), 0) << "a beam from a misread packet";
  EXPECT_GT(laser.status().skipped_bytes, 0u);
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
}

TEST_P(LdsLaserTest, UnpluggedItSaysSoAndScansAgainOncePluggedBackIn) {
  const std::filesystem::path link = Link("unplug");
  LdsEmulator device(link, Emulated());
  SteadyClock clock;
  LdsLaser laser(OptionsFor(link, GetParam()), clock);
  RoomScans received(Room);
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Unplug();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kDisconnected; }, 3000ms))
      << ToString(laser.status().state);
  EXPECT_FALSE(laser.status().last_error.empty());
  const int before = received.count();
  device.Replug();  // an LDS-01 powered up anew waits for its start
  ASSERT_TRUE(Eventually([&] { return received.count() >= before + 2; }, 5000ms)) << laser.status().last_error;
  EXPECT_EQ(laser.status().state, LinkState::kRunning);
  EXPECT_GT(laser.status().reconnects, 0u);
  EXPECT_EQ(received.wrong(), 0);
}

TEST_P(LdsLaserTest, ADeviceThatFallsSilentIsStaleThenSilentAndScansAgainWhenItSends) {
  const std::filesystem::path link = Link("silent");
  LdsEmulator device(link, Emulated());
  SteadyClock clock;
  LdsLaser laser(OptionsFor(link, GetParam()), clock);
  RoomScans received(Room);
  std::mutex mutex;
  std::vector<LinkState> states;
  laser.SetLinkHandler([&](const LinkStatus& status) {
    std::lock_guard lock(mutex);
    states.push_back(status.state);
  });
  received.Connect(laser);
  ASSERT_TRUE(Eventually([&] { return received.count() >= 2; }, 5000ms)) << laser.status().last_error;
  device.Silence();
  ASSERT_TRUE(Eventually([&] { return laser.status().state == LinkState::kSilent; }, 3000ms));
  {
    std::lock_guard lock(mutex);
    EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end());
  }
  const int before = received.count();
  device.Resume();
  ASSERT_TRUE(Eventually([&] { return received.count() >= before + 2; }, 5000ms)) << laser.status().last_error;
  if (lds01()) {
    EXPECT_GE(device.starts(), 1);
  }
}

TEST(LdsLaserOptionsTest, ANamelessPortOrBadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(LdsLaser(LdsOptions{}, clock), std::invalid_argument);
  LdsOptions options = OptionsFor("/dev/null", Model::kLds02);
  options.silence_s = 0.0;
  EXPECT_THROW(LdsLaser(options, clock), std::invalid_argument);
  options = OptionsFor("/dev/null", Model::kLds02);
  options.sweep.bins = 2;
  EXPECT_THROW(LdsLaser(options, clock), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Models, LdsLaserTest, ::testing::Values(Model::kLds01, Model::kLds02),
                         [](const auto& model) { return model.param == Model::kLds01 ? "Lds01" : "Lds02"; });

}  // namespace
}  // namespace corridor::drivers::lds
