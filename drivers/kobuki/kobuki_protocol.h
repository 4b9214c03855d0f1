// The Kobuki's serial protocol (the base of a TurtleBot 2), from Yujin Robot's public "Kobuki Protocol Specification":
// packets of two header bytes (0xAA 0x55), a length, a payload of sub-payloads (an id, a length, the data), and a
// checksum (the XOR of the length and every payload byte). The host sends commands (Base Control: a speed and a
// radius); the Kobuki streams feedback at 50 Hz without being asked (Basic Sensor Data: time stamp, bumpers, wheel
// drops, cliffs, both encoders, PWM, buttons, charger, battery, over-current; Inertial Sensor: the gyro's heading).
// Multi-byte numbers are little-endian. Bytes in and out only; the driver does the I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::drivers::kobuki {

inline constexpr std::uint8_t kHeader0 = 0xAA;
inline constexpr std::uint8_t kHeader1 = 0x55;

// Sub-payload ids (the specification's "Command Packets" and "Feedback Packets").
enum class Command : std::uint8_t { kBaseControl = 1, kSound = 3, kRequestExtra = 9 };
enum class Feedback : std::uint8_t {
  kBasicSensorData = 1,       // 15 bytes
  kDockingIr = 3,             // 3
  kInertialSensor = 4,        // 7
  kCliff = 5,                 // 6
  kCurrent = 6,               // 2
  kHardwareVersion = 10,      // 4
  kFirmwareVersion = 11,      // 4
  kRawGyro = 13,              // 2 + 6n
  kGeneralPurposeInput = 16,  // 16
  kUniqueDeviceId = 19,       // 12
};

// One packet: the payload's bytes wrapped in headers, length and checksum. Throws std::invalid_argument for a payload
// over 255 bytes.
std::vector<std::uint8_t> EncodePacket(std::span<const std::uint8_t> payload);

// Base Control: the robot follows an arc of `radius_mm` (positive: its centre to the left) with its outer wheel at
// `speed_mmps` (the wheel farther from the arc's centre; negative: backwards). Two radii mean more: 0 drives straight
// at the speed, 1 turns on the spot with each wheel at the speed (positive: counter-clockwise).
struct BaseControl {
  int speed_mmps = 0;
  int radius_mm = 0;
};
std::vector<std::uint8_t> EncodeBaseControl(const BaseControl& command);  // a whole packet
// The Base Control that drives `twist` on wheels `track_m` apart, each wheel's speed rounded to the mm/s.
BaseControl ToBaseControl(const nav::Twist2& twist, double track_m);

// Basic Sensor Data, decoded.
struct SensorData {
  std::uint16_t timestamp_ms = 0;
  bool bump_left = false;
  bool bump_centre = false;
  bool bump_right = false;
  bool wheel_drop_left = false;
  bool wheel_drop_right = false;
  bool cliff = false;  // any of the three cliff sensors
  std::uint16_t left_counts = 0;
  std::uint16_t right_counts = 0;
  int charger = 0;  // 0 discharging; 2/6 on the dock charged/charging; 18/22 on the adapter charged/charging
  double battery_v = 0.0;
  bool over_current = false;
};
bool Charging(int charger);  // current flows into the battery
bool OnDock(int charger);    // the dock's contacts are connected

// Everything one feedback packet said that the driver reads.
struct FeedbackPacket {
  std::optional<SensorData> sensors;
  std::optional<double> heading_rad;  // the gyro's heading (counter-clockwise), from Inertial Sensor
};

// Feedback packets from the stream as the serial port delivers it, in pieces of any size. A packet whose checksum
// fails, or whose sub-payloads do not fill its length exactly, is dropped (`dropped()`), and the parser looks for the
// next header after its first byte; bytes before a header are skipped (`skipped()`). Sub-payloads of ids it does not
// read are passed over by their length.
class PacketParser {
 public:
  void Push(std::span<const std::uint8_t> bytes, std::vector<FeedbackPacket>& out);
  std::uint64_t dropped() const { return dropped_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  std::vector<std::uint8_t> pending_;
  std::uint64_t dropped_ = 0;
  std::uint64_t skipped_ = 0;
};

}  // namespace corridor::drivers::kobuki
