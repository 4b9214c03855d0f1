// The pan servo driver against an emulated X-series servo on a pseudo-terminal (testing/emulators/x_servo_emulator.h):
// real serial I/O on real threads, since the transport is the point; every wait is for a condition, with a deadline.
#include "drivers/dynamixel/pan_servo.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include "testing/emulators/x_servo_emulator.h"
#include "testing/eventually.h"

namespace corridor::drivers::dynamixel {
namespace {

using corridor::testing::Eventually;
using corridor::testing::XServoEmulator;
using namespace std::chrono_literals;

constexpr double kDeg = std::numbers::pi / 180.0;

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_pan_" + name + "_" + std::to_string(::getpid()));
}

PanServoOptions OptionsFor(const std::filesystem::path& port) {
  PanServoOptions options;
  options.port = port;
  options.id = 3;
  options.reconnect_s = 0.1;
  return options;
}

// The readings the driver hands on, the last kept.
struct Readings {
  std::mutex mutex;
  std::vector<PanReading> all;
  void Connect(PanServo& servo) {
    servo.SetReadingHandler([this](const PanReading& r) {
      std::lock_guard lock(mutex);
      all.push_back(r);
    });
  }
  PanReading last() {
    std::lock_guard lock(mutex);
    return all.empty() ? PanReading{} : all.back();
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return all.size();
  }
};

TEST(DynamixelPanServoTest, ItTurnsTheTorqueOnAndTheCameraToItsTargetAndReportsWhereItIs) {
  const std::filesystem::path link = Link("turn");
  XServoEmulator servo(link, 3, 2048 + 100);  // left where it was, 8.8 degrees to the left
  SteadyClock clock;
  DynamixelPanServo pan(OptionsFor(link), clock);
  Readings readings;
  readings.Connect(pan);
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kRunning; }, 3000ms)) << pan.status().last_error;
  EXPECT_EQ(pan.status().model_number, 1060);
  EXPECT_TRUE(servo.torque());
  // Its first goal is straight ahead; then 40 degrees to the left (counter-clockwise, counting up).
  ASSERT_TRUE(Eventually([&] { return std::abs(readings.last().pan_rad) < 0.5 * kDeg; }, 3000ms))
      << readings.last().pan_rad / kDeg;
  pan.SetTarget(40.0 * kDeg);
  EXPECT_TRUE(Eventually([&] { return std::abs(readings.last().velocity_rps) > 30.0 * kDeg; }, 2000ms))
      << "it turns at its profile velocity (90 degrees/s)";
  // There, and still (it slows down onto its goal).
  ASSERT_TRUE(Eventually(
      [&] {
        const PanReading r = readings.last();
        return std::abs(r.pan_rad - 40.0 * kDeg) < 0.1 * kDeg && std::abs(r.velocity_rps) < 1.0 * kDeg;
      },
      3000ms))
      << readings.last().pan_rad / kDeg << " degrees at " << readings.last().velocity_rps / kDeg << " degrees/s";
  EXPECT_NEAR(servo.position(), 2048 + 40.0 / 360.0 * 4096, 1.0);
  // A target beyond the limits stops at the limit (the servo is never sent a goal it would refuse).
  pan.SetTarget(-200.0 * kDeg);
  ASSERT_TRUE(Eventually([&] { return std::abs(readings.last().pan_rad + 150.0 * kDeg) < 0.2 * kDeg; }, 5000ms))
      << readings.last().pan_rad / kDeg;
  EXPECT_EQ(pan.status().device_errors, 0u);
  EXPECT_EQ(servo.crc_errors(), 0);
  EXPECT_GE(pan.status().reads, 50u);
  // Readings are stamped in order on the host's clock, about every poll period.
  std::lock_guard lock(readings.mutex);
  EXPECT_TRUE(std::is_sorted(readings.all.begin(), readings.all.end(),
                             [](const PanReading& a, const PanReading& b) { return a.stamp_ns < b.stamp_ns; }));
}

TEST(DynamixelPanServoTest, AServoHungUpsideDownWithItsCentreElsewhereIsTurnedTheOtherWay) {
  const std::filesystem::path link = Link("reversed");
  XServoEmulator servo(link, 3, 1000);
  SteadyClock clock;
  PanServoOptions options = OptionsFor(link);
  options.reversed = true;
  options.center_position = 1024;
  options.min_deg = -60.0;
  options.max_deg = 60.0;
  DynamixelPanServo pan(options, clock);
  EXPECT_EQ(pan.ToPosition(0.0), 1024);
  EXPECT_EQ(pan.ToPosition(90.0 * kDeg), 0);
  EXPECT_NEAR(pan.ToPan(2048), -90.0 * kDeg, 1e-9);
  pan.SetTarget(30.0 * kDeg);  // to the left: counting down
  ASSERT_TRUE(Eventually([&] { return std::abs(servo.position() - (1024 - 4096.0 / 12.0)) < 1.0; }, 4000ms))
      << servo.position();
  ASSERT_TRUE(Eventually([&] { return std::abs(pan.status().pan_rad - 30.0 * kDeg) < 0.2 * kDeg; }, 1000ms));
}

TEST(DynamixelPanServoTest, NoiseABadCrcAndASlowServoCostAReadNotTheLink) {
  const std::filesystem::path link = Link("noise");
  XServoEmulator servo(link, 3, 2048);
  SteadyClock clock;
  DynamixelPanServo pan(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return pan.status().reads >= 5; }, 3000ms)) << pan.status().last_error;
  servo.Noise({0xFF, 0xFF, 0xFD, 0x00, 0x03, 0xFF, 0x7F, 0x13, 0x00, 0xFD});  // a header whose length is absurd
  servo.BadCrc();
  ASSERT_TRUE(Eventually([&] { return pan.status().dropped_packets >= 1; }, 2000ms));
  const std::uint64_t reads = pan.status().reads;
  ASSERT_TRUE(Eventually([&] { return pan.status().reads >= reads + 5; }, 2000ms));
  // Answers 30 ms late (later than a cycle, sooner than stale): still running, still turning.
  servo.Slow(0.03);
  pan.SetTarget(-20.0 * kDeg);
  ASSERT_TRUE(Eventually([&] { return std::abs(pan.status().pan_rad + 20.0 * kDeg) < 0.2 * kDeg; }, 3000ms));
  EXPECT_EQ(pan.status().state, LinkState::kRunning);
}

TEST(DynamixelPanServoTest, SilentOrUnpluggedItIsStaleThenReconnectsAndHoldsItsTargetAgain) {
  const std::filesystem::path link = Link("unplug");
  XServoEmulator servo(link, 3, 2048);
  SteadyClock clock;
  DynamixelPanServo pan(OptionsFor(link), clock);
  std::vector<LinkState> states;
  std::mutex mutex;
  pan.SetLinkHandler([&](const LinkStatus& s) {
    std::lock_guard lock(mutex);
    states.push_back(s.state);
  });
  pan.SetTarget(25.0 * kDeg);
  ASSERT_TRUE(Eventually([&] { return std::abs(pan.status().pan_rad - 25.0 * kDeg) < 0.2 * kDeg; }, 3000ms))
      << pan.status().last_error;
  servo.Silence();
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kSilent; }, 2000ms));
  {
    std::lock_guard lock(mutex);
    EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end()) << "stale before silent";
  }
  servo.Resume();
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kRunning; }, 3000ms));
  servo.Unplug();
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kDisconnected; }, 3000ms));
  servo.Replug();  // restarted: torque off until the driver sets it up again
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(pan.status().state) << " " << pan.status().last_error;
  EXPECT_TRUE(servo.torque());
  pan.SetTarget(-10.0 * kDeg);
  ASSERT_TRUE(Eventually([&] { return std::abs(pan.status().pan_rad + 10.0 * kDeg) < 0.2 * kDeg; }, 3000ms));
  EXPECT_GT(pan.status().reconnects, 0u);
}

TEST(DynamixelPanServoTest, AnOverloadedServoIsRebootedAndSetUpAgain) {
  const std::filesystem::path link = Link("overload");
  XServoEmulator servo(link, 3, 2048);
  SteadyClock clock;
  DynamixelPanServo pan(OptionsFor(link), clock);
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kRunning; }, 3000ms));
  servo.Overload();  // it lets go and raises the alert bit in every answer
  ASSERT_TRUE(Eventually([&] { return servo.reboots() == 1; }, 2000ms)) << pan.status().last_error;
  EXPECT_EQ(pan.status().hardware_error, 0x20);
  ASSERT_TRUE(Eventually([&] { return pan.status().state == LinkState::kRunning && servo.torque(); }, 3000ms));
  EXPECT_EQ(servo.hardware_error(), 0);
  EXPECT_EQ(pan.status().reboots, 1u);
  pan.SetTarget(15.0 * kDeg);
  ASSERT_TRUE(Eventually([&] { return std::abs(pan.status().pan_rad - 15.0 * kDeg) < 0.2 * kDeg; }, 3000ms));
}

TEST(DynamixelPanServoTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(DynamixelPanServo(PanServoOptions{}, clock), std::invalid_argument);
  PanServoOptions options = OptionsFor("/dev/null");
  options.id = 253;
  EXPECT_THROW(DynamixelPanServo(options, clock), std::invalid_argument);
  options = OptionsFor("/dev/null");
  options.min_deg = 10.0;
  EXPECT_THROW(DynamixelPanServo(options, clock), std::invalid_argument);
  options = OptionsFor("/dev/null");
  options.silence_s = options.stale_s;
  EXPECT_THROW(DynamixelPanServo(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::dynamixel
