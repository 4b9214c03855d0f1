// The OpenCR board of a TurtleBot 3 as a DYNAMIXEL Protocol 2.0 device (dynamixel_protocol.h), per the control table
// ROBOTIS's e-Manual gives for its TurtleBot 3 firmware (the one ROS 2's turtlebot3_node talks to): device 200 at
// 1 Mbps; values little-endian, signed where they can be negative.
#pragma once

#include <cstdint>

namespace corridor::drivers::turtlebot3 {

inline constexpr std::uint8_t kOpenCrId = 200;

namespace address {
inline constexpr std::uint16_t kModelNumber = 0;  // 2 bytes
inline constexpr std::uint16_t kHeartbeat = 19;   // 1 byte, written by the host to say it is there
inline constexpr std::uint16_t kButton1 = 26;     // 1 byte each: 1 pressed
inline constexpr std::uint16_t kButton2 = 27;
inline constexpr std::uint16_t kBumper1 = 28;
inline constexpr std::uint16_t kBumper2 = 29;
inline constexpr std::uint16_t kBatteryVoltage = 42;        // int32, 0.01 V
inline constexpr std::uint16_t kBatteryPercentage = 46;     // int32, 0.01 %
inline constexpr std::uint16_t kPresentVelocityLeft = 128;  // int32, the servo's unit (0.229 rpm)
inline constexpr std::uint16_t kPresentVelocityRight = 132;
inline constexpr std::uint16_t kPresentPositionLeft = 136;  // int32, 4096 a turn of the wheel
inline constexpr std::uint16_t kPresentPositionRight = 140;
inline constexpr std::uint16_t kMotorTorqueEnable = 149;  // 1 byte: 1 the wheels are driven
// Six int32: linear x, y, z in 0.01 m/s, angular x, y, z in 0.01 rad/s (the board drives linear x and angular z).
inline constexpr std::uint16_t kCmdVelocityLinearX = 150;
inline constexpr std::uint16_t kCmdVelocityAngularZ = 170;
}  // namespace address

// What the driver reads every cycle: the buttons through the wheels' positions, in one Read.
inline constexpr std::uint16_t kStateFirst = address::kButton1;
inline constexpr std::uint16_t kStateLength = address::kPresentPositionRight + 4 - kStateFirst;

}  // namespace corridor::drivers::turtlebot3
