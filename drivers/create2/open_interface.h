// The iRobot Create 2 (and Roomba 600-900) Open Interface, from iRobot's public "Create 2 Open Interface (OI)
// Specification": the commands a driver sends (Start, Safe, Drive Direct, Stream, Stop) and the sensor stream it reads
// back (header 19, a byte count, packet ids with their data, and a checksum that makes the whole frame sum to zero),
// decoded into what the robot needs: wheel encoder counts, bumps, wheel drops, cliffs, battery and charging. Bytes
// in and out only; the driver does the I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::create2 {

// Opcodes (OI specification, "Open Interface Commands").
enum class Opcode : std::uint8_t {
  kReset = 7,
  kStart = 128,
  kSafe = 131,
  kFull = 132,
  kSeekDock = 143,
  kDriveDirect = 145,
  kStream = 148,
  kPauseResumeStream = 150,
  kStop = 173,
};

// Sensor packet ids the driver streams, and their sizes in bytes.
enum class Packet : std::uint8_t {
  kBumpsAndWheelDrops = 7,  // 1: bit 0 bump right, 1 bump left, 2 wheel drop right, 3 wheel drop left
  kCliffLeft = 9,           // 1 each: 0 or 1
  kCliffFrontLeft = 10,
  kCliffFrontRight = 11,
  kCliffRight = 12,
  kVirtualWall = 13,           // 1: sized only (the driver does not stream it)
  kChargingState = 21,         // 1: 0 not charging .. 5 charging fault
  kVoltage = 22,               // 2: mV, unsigned
  kCurrent = 23,               // 2: mA, signed (negative: discharging)
  kBatteryCharge = 25,         // 2: mAh, unsigned
  kBatteryCapacity = 26,       // 2: mAh, unsigned
  kCliffFrontLeftSignal = 29,  // 2: sized only
  kChargingSources = 34,       // 1: bit 0 internal charger, bit 1 home base
  kOiMode = 35,                // 1: 0 off, 1 passive, 2 safe, 3 full
  kLeftEncoderCounts = 43,     // 2: unsigned, wrapping at 65535
  kRightEncoderCounts = 44,
};
// The size of a packet's data, or nothing for an id this decoder does not know.
std::optional<std::size_t> PacketSize(std::uint8_t id);

// The packets corridor's driver streams, in order.
const std::vector<Packet>& StreamedPackets();

// Commands. Drive Direct takes each wheel's velocity in mm/s (clamped to the OI's +-500), right wheel first, each a
// signed 16-bit big-endian number.
std::vector<std::uint8_t> EncodeStart();
std::vector<std::uint8_t> EncodeSafe();
std::vector<std::uint8_t> EncodeStop();
std::vector<std::uint8_t> EncodeDriveDirect(int left_mmps, int right_mmps);
std::vector<std::uint8_t> EncodeStream(std::span<const Packet> packets);
std::vector<std::uint8_t> EncodePauseStream(bool resume);

// One sensor frame of the stream, decoded.
struct SensorFrame {
  bool bump_left = false;
  bool bump_right = false;
  bool wheel_drop_left = false;
  bool wheel_drop_right = false;
  bool cliff = false;  // any of the four cliff sensors
  int charging_state = 0;
  double voltage_v = 0.0;
  double current_a = 0.0;
  double charge_ah = 0.0;
  double capacity_ah = 0.0;
  bool on_home_base = false;
  int oi_mode = 0;
  std::uint16_t left_counts = 0;
  std::uint16_t right_counts = 0;
  bool has_encoders = false;  // both encoder packets were in the frame
};

// Frames from the stream as the serial port delivers it, in pieces of any size. A frame whose checksum fails, or
// whose packets do not fill its byte count exactly, is dropped and the parser looks for the next header byte after
// its start; `dropped()` counts them. A header byte followed by a count over kMaxFrameBytes or by an unknown packet id
// begins no frame (noise is not waited on for hundreds of bytes).
class StreamParser {
 public:
  static constexpr std::size_t kMaxFrameBytes = 64;
  void Push(std::span<const std::uint8_t> bytes, std::vector<SensorFrame>& out);
  std::uint64_t dropped() const { return dropped_; }
  void Clear() { pending_.clear(); }

 private:
  std::vector<std::uint8_t> pending_;
  std::uint64_t dropped_ = 0;
};

// The Create 2's wheels: 72 mm across, 235 mm apart, 508.8 counts a turn (OI specification, packets 43-44); its
// encoders' counts wrap at 65535 (drivers/wheels/encoder_odometry.h).
inline constexpr WheelGeometry kCreate2Wheels{0.072, 0.235, 508.8};

}  // namespace corridor::drivers::create2
