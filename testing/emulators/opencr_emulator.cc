#include "testing/emulators/opencr_emulator.h"

#include <cmath>
#include <cstdint>
#include <numbers>

namespace corridor::testing {
namespace {

constexpr std::uint8_t kId = 200;
constexpr double kTicksPerMetre = 4096.0 / (std::numbers::pi * 0.066);
constexpr double kOpenCrTrackM = 0.160;
constexpr double kVelocityUnitMps = 0.229 / 60.0 * std::numbers::pi * 0.066;  // 0.229 rpm of a 66 mm wheel
// The control table's addresses (the e-Manual's TurtleBot 3 OpenCR table).
constexpr std::size_t kModelNumber = 0;
constexpr std::size_t kHeartbeat = 19;
constexpr std::size_t kBumper1 = 28;
constexpr std::size_t kBatteryVoltage = 42;
constexpr std::size_t kBatteryPercentage = 46;
constexpr std::size_t kPresentVelocityLeft = 128;
constexpr std::size_t kPresentVelocityRight = 132;
constexpr std::size_t kPresentPositionLeft = 136;
constexpr std::size_t kPresentPositionRight = 140;
constexpr std::size_t kTorqueEnable = 149;
constexpr std::size_t kCmdLinearX = 150;
constexpr std::size_t kCmdAngularZ = 170;
constexpr std::size_t kTableEnd = 182;  // past the profile accelerations
constexpr std::uint16_t kModel = 0x5000;

}  // namespace

OpenCrEmulator::OpenCrEmulator(std::filesystem::path link) : DynamixelEmulator(std::move(link), kId, kTableEnd) {
  table_[kModelNumber] = kModel & 0xFF;
  table_[kModelNumber + 1] = kModel >> 8;
  SetInt32(kBatteryVoltage, 1190);
  SetInt32(kBatteryPercentage, 8000);
  Start();
}

OpenCrEmulator::~OpenCrEmulator() { Stop(); }

std::pair<double, double> OpenCrEmulator::wheels_mps() const {
  std::lock_guard lock(mutex_);
  return {left_mps_, right_mps_};
}
bool OpenCrEmulator::torque() const {
  std::lock_guard lock(mutex_);
  return table_[kTorqueEnable] != 0;
}
int OpenCrEmulator::heartbeats() const {
  std::lock_guard lock(mutex_);
  return heartbeats_;
}
void OpenCrEmulator::SetBumper(bool pressed) {
  std::lock_guard lock(mutex_);
  table_[kBumper1] = pressed ? 1 : 0;
}
void OpenCrEmulator::SetBattery(double volts, double percent) {
  std::lock_guard lock(mutex_);
  SetInt32(kBatteryVoltage, static_cast<std::int32_t>(std::lround(volts * 100.0)));
  SetInt32(kBatteryPercentage, static_cast<std::int32_t>(std::lround(percent * 100.0)));
}

void OpenCrEmulator::Restarted() {
  table_[kTorqueEnable] = 0;
  for (std::size_t a = kCmdLinearX; a < kCmdAngularZ + 4; ++a) table_[a] = 0;
}

void OpenCrEmulator::Written(std::size_t address, std::size_t length) {
  if (address <= kHeartbeat && kHeartbeat < address + length) ++heartbeats_;
}

void OpenCrEmulator::Advance(double dt_s) {
  // The wheels, as the velocity command says while the torque is on.
  const bool driven = table_[kTorqueEnable] != 0;
  const double v = driven ? Int32At(kCmdLinearX) / 100.0 : 0.0;
  const double w = driven ? Int32At(kCmdAngularZ) / 100.0 : 0.0;
  left_mps_ = v - w * kOpenCrTrackM / 2.0;
  right_mps_ = v + w * kOpenCrTrackM / 2.0;
  left_ticks_ += left_mps_ * dt_s * kTicksPerMetre;
  right_ticks_ += right_mps_ * dt_s * kTicksPerMetre;
  const auto wrapped = [](double ticks) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(std::floor(ticks))));
  };
  SetInt32(kPresentPositionLeft, wrapped(left_ticks_));
  SetInt32(kPresentPositionRight, wrapped(right_ticks_));
  SetInt32(kPresentVelocityLeft, static_cast<std::int32_t>(std::lround(left_mps_ / kVelocityUnitMps)));
  SetInt32(kPresentVelocityRight, static_cast<std::int32_t>(std::lround(right_mps_ / kVelocityUnitMps)));
}

}  // namespace corridor::testing
