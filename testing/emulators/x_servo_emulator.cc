#include "testing/emulators/x_servo_emulator.h"

#include <algorithm>
#include <cmath>

namespace corridor::testing {
namespace {
// The X-series control table (the e-Manual's XL430-W250 page), named apart from the other emulators' tables.
namespace x_table {

constexpr std::size_t kModelNumber = 0;
constexpr std::size_t kId = 7;
constexpr std::size_t kVelocityLimit = 44;
constexpr std::size_t kMaxPositionLimit = 48;
constexpr std::size_t kMinPositionLimit = 52;
constexpr std::size_t kEepromEnd = 64;
constexpr std::size_t kTorqueEnable = 64;
constexpr std::size_t kProfileAcceleration = 108;
constexpr std::size_t kProfileVelocity = 112;
constexpr std::size_t kGoalPosition = 116;
constexpr std::size_t kReadOnlyFrom = 120;  // Realtime Tick on
constexpr std::size_t kMoving = 122;
constexpr std::size_t kPresentVelocity = 128;
constexpr std::size_t kPresentPosition = 132;
constexpr std::size_t kPresentTemperature = 146;
constexpr std::size_t kTableEnd = 147;
constexpr std::uint16_t kModel = 1060;
constexpr std::uint8_t kDataRangeError = 0x04;
constexpr std::uint8_t kAccessError = 0x07;
constexpr std::uint8_t kOverload = 0x20;
// Units: velocity 0.229 rev/min, acceleration 214.577 rev/min^2, 4096 counts a turn.
constexpr double kCountsPerSecondPerVelocityUnit = 0.229 / 60.0 * 4096.0;
constexpr double kCountsPerSecond2PerAccelerationUnit = 214.577 / 3600.0 * 4096.0;

}  // namespace x_table
}  // namespace

XServoEmulator::XServoEmulator(std::filesystem::path link, std::uint8_t id, double position)
    : DynamixelEmulator(std::move(link), id, x_table::kTableEnd), position_(position) {
  table_[x_table::kModelNumber] = x_table::kModel & 0xFF;
  table_[x_table::kModelNumber + 1] = x_table::kModel >> 8;
  table_[x_table::kId] = id;
  SetInt32(x_table::kVelocityLimit, 265);  // 61 rev/min
  SetInt32(x_table::kMaxPositionLimit, 4095);
  SetInt32(x_table::kMinPositionLimit, 0);
  table_[x_table::kPresentTemperature] = 31;
  Restarted();
  Start();
}

XServoEmulator::~XServoEmulator() { Stop(); }

double XServoEmulator::position() const {
  std::lock_guard lock(mutex_);
  return position_;
}
std::int32_t XServoEmulator::goal() const {
  std::lock_guard lock(mutex_);
  return Int32At(x_table::kGoalPosition);
}
bool XServoEmulator::torque() const {
  std::lock_guard lock(mutex_);
  return table_[x_table::kTorqueEnable] != 0;
}
int XServoEmulator::hardware_error() const {
  std::lock_guard lock(mutex_);
  return table_[kHardwareErrorStatus];
}
void XServoEmulator::Overload() {
  std::lock_guard lock(mutex_);
  table_[kHardwareErrorStatus] = x_table::kOverload;
  table_[x_table::kTorqueEnable] = 0;
}

void XServoEmulator::Restarted() {
  // The RAM area back to its defaults: torque off, no profile, the goal where the shaft is.
  std::fill(table_.begin() + x_table::kEepromEnd, table_.end(), 0);
  table_[x_table::kPresentTemperature] = 31;
  SetInt32(x_table::kGoalPosition, static_cast<std::int32_t>(std::lround(position_)));
  velocity_ = 0.0;
  Advance(0.0);
}

std::uint8_t XServoEmulator::Check(std::size_t address, std::span<const std::uint8_t> data) const {
  if (address < x_table::kEepromEnd && table_[x_table::kTorqueEnable] != 0) return x_table::kAccessError;
  if (address + data.size() > x_table::kReadOnlyFrom) return x_table::kAccessError;
  if (address == x_table::kGoalPosition && data.size() == 4) {
    const auto goal =
        static_cast<std::int32_t>(data[0] | data[1] << 8 | data[2] << 16 | static_cast<std::uint32_t>(data[3]) << 24);
    if (goal < Int32At(x_table::kMinPositionLimit) || goal > Int32At(x_table::kMaxPositionLimit))
      return x_table::kDataRangeError;
  }
  return 0;
}

void XServoEmulator::Advance(double dt_s) {
  if (table_[x_table::kTorqueEnable] == 0) {
    velocity_ = 0.0;
  } else {
    const std::int32_t profile = Int32At(x_table::kProfileVelocity);
    const double top =
        (profile > 0 ? std::min(profile, Int32At(x_table::kVelocityLimit)) : Int32At(x_table::kVelocityLimit)) *
        x_table::kCountsPerSecondPerVelocityUnit;
    const std::int32_t profile_accel = Int32At(x_table::kProfileAcceleration);
    const double accel = profile_accel > 0 ? profile_accel * x_table::kCountsPerSecond2PerAccelerationUnit : 1e6;
    const double to_go = Int32At(x_table::kGoalPosition) - position_;
    // Toward the goal as fast as the profile allows and still stops on it.
    const double wanted = std::copysign(std::min(top, std::sqrt(2.0 * accel * std::abs(to_go))), to_go);
    velocity_ += std::clamp(wanted - velocity_, -accel * dt_s, accel * dt_s);
    const double step = velocity_ * dt_s;
    if (std::abs(step) >= std::abs(to_go)) {
      position_ = Int32At(x_table::kGoalPosition);
      velocity_ = 0.0;
    } else {
      position_ += step;
    }
  }
  SetInt32(x_table::kPresentPosition, static_cast<std::int32_t>(std::lround(position_)));
  SetInt32(x_table::kPresentVelocity,
           static_cast<std::int32_t>(std::lround(velocity_ / x_table::kCountsPerSecondPerVelocityUnit)));
  table_[x_table::kMoving] = std::abs(Int32At(x_table::kGoalPosition) - position_) > 0.5 ? 1 : 0;
}

}  // namespace corridor::testing
