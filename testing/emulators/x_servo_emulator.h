// An X-series DYNAMIXEL servo (an XL430-W250, model 1060) for tests, on a pseudo-terminal: a Protocol 2.0 device
// (dynamixel_emulator.h, with its faults) holding the servo's control table as ROBOTIS's e-Manual gives it, written
// from that document apart from the driver's table. With the torque on it turns toward its goal position with the
// profile's velocity and acceleration (a trapezoid; the velocity limit when the profile velocity is 0), reporting its
// present position and velocity; writes to the EEPROM area with the torque on are refused (access error), goals
// outside the position limits too (data range error). Beyond the link's faults, an overload: the servo lets go
// (torque off), reports hardware error status 0x20 and sets the alert bit in every answer until it is rebooted (or
// replugged).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

#include "testing/emulators/dynamixel_emulator.h"

namespace corridor::testing {

class XServoEmulator final : public DynamixelEmulator {
 public:
  // Servo `id`, its shaft at `position` counts.
  XServoEmulator(std::filesystem::path link, std::uint8_t id, double position);
  ~XServoEmulator() override;

  double position() const;  // counts, as turned
  std::int32_t goal() const;
  bool torque() const;
  int hardware_error() const;
  void Overload();

 private:
  void Advance(double dt_s) override;
  std::uint8_t Check(std::size_t address, std::span<const std::uint8_t> data) const override;
  void Restarted() override;
  bool alert() const override { return table_[kHardwareErrorStatus] != 0; }

  static constexpr std::size_t kHardwareErrorStatus = 70;
  double position_;
  double velocity_ = 0.0;  // counts a second
};

}  // namespace corridor::testing
