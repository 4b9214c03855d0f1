// DYNAMIXEL Protocol 2.0, as ROBOTIS's e-Manual documents it: the packets a host and a device (a DYNAMIXEL servo such
// as a camera's pan servo, or the OpenCR board of a TurtleBot 3, which answers as device 200) exchange over a serial
// line.
//   instruction: FF FF FD 00 | id | length (LE16) | instruction | parameters | CRC (LE16)
//   status:      FF FF FD 00 | id | length (LE16) | 0x55 | error | parameters | CRC (LE16)
// The length counts what follows it (instruction, error, parameters, CRC). Inside the packet, FF FF FD is followed by
// an extra FD (byte stuffing) so that no header appears in the middle of one; the length counts the stuffed bytes. The
// CRC is CRC-16 with polynomial 0x8005 (initial 0, not reflected) over everything before it, header included.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace corridor::drivers::dynamixel {

enum class Instruction : std::uint8_t { kPing = 0x01, kRead = 0x02, kWrite = 0x03, kReboot = 0x08, kStatus = 0x55 };

// The error byte of a status packet: its low 7 bits a number (0 none), its top bit the device's hardware alert.
inline constexpr std::uint8_t kAlertBit = 0x80;

std::uint16_t Crc16(std::span<const std::uint8_t> bytes);

// A whole instruction packet, stuffed and checked.
std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> parameters);
std::vector<std::uint8_t> EncodePing(std::uint8_t id);
std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint16_t address, std::uint16_t length);
std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data);
// A restart of the device: what clears a servo's hardware error (its torque off after).
std::vector<std::uint8_t> EncodeReboot(std::uint8_t id);

struct StatusPacket {
  std::uint8_t id = 0;
  std::uint8_t error = 0;
  std::vector<std::uint8_t> parameters;  // unstuffed
};

// Status packets out of the bytes as they arrive, in pieces: what does not begin a packet is skipped, a packet whose
// CRC fails (or that is not a status packet, or too short to be one) is dropped and counted.
class StatusParser {
 public:
  void Push(std::span<const std::uint8_t> bytes, std::vector<StatusPacket>& out);
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::uint64_t dropped_ = 0;
};

// Little-endian values in a control table's bytes.
std::int32_t ReadInt32(std::span<const std::uint8_t> bytes, std::size_t at);
void AppendInt32(std::vector<std::uint8_t>& out, std::int32_t value);

}  // namespace corridor::drivers::dynamixel
