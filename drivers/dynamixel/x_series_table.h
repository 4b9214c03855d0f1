// The control table of ROBOTIS's X-series DYNAMIXEL servos (XL430, XC430, XM430, XH430, ...) under Protocol 2.0
// (dynamixel_protocol.h), as the e-Manual gives it: what the camera's pan servo driver reads and writes. Values are
// little-endian, signed where they can be negative. Below address 64 is the EEPROM area, writable only with the
// torque off; from 64 on, RAM.
#pragma once

#include <cstdint>
#include <numbers>

namespace corridor::drivers::dynamixel::x_series {

namespace address {
inline constexpr std::uint16_t kModelNumber = 0;            // 2 bytes
inline constexpr std::uint16_t kTorqueEnable = 64;          // 1 byte: 1 the servo holds its goal
inline constexpr std::uint16_t kHardwareErrorStatus = 70;   // 1 byte: bit 0 voltage, 2 overheating, 3 encoder,
                                                            // 4 electrical shock, 5 overload
inline constexpr std::uint16_t kProfileAcceleration = 108;  // uint32, 214.577 rev/min^2
inline constexpr std::uint16_t kProfileVelocity = 112;      // uint32, 0.229 rev/min; 0: as fast as it can
inline constexpr std::uint16_t kGoalPosition = 116;         // int32, counts
inline constexpr std::uint16_t kMoving = 122;               // 1 byte
inline constexpr std::uint16_t kPresentVelocity = 128;      // int32, 0.229 rev/min
inline constexpr std::uint16_t kPresentPosition = 132;      // int32, counts
inline constexpr std::uint16_t kPresentTemperature = 146;   // 1 byte, degrees Celsius
}  // namespace address

// One turn of the output shaft is 4096 counts (0.088 degrees each); 2048 is the middle of the single-turn range
// 0-4095, counter-clockwise (seen from the horn) counting up.
inline constexpr double kCountsPerTurn = 4096.0;
inline constexpr double kRadPerCount = 2.0 * std::numbers::pi / kCountsPerTurn;
inline constexpr double kRpsPerVelocityUnit = 0.229 * 2.0 * std::numbers::pi / 60.0;  // 0.229 rev/min
inline constexpr double kRps2PerAccelerationUnit = 214.577 * 2.0 * std::numbers::pi / 3600.0;

// What the driver reads every cycle, in one Read: the present velocity and position.
inline constexpr std::uint16_t kStateFirst = address::kPresentVelocity;
inline constexpr std::uint16_t kStateLength = address::kPresentPosition + 4 - kStateFirst;

}  // namespace corridor::drivers::dynamixel::x_series
