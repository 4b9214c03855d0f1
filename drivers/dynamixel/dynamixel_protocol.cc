#include "drivers/dynamixel/dynamixel_protocol.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace corridor::drivers::dynamixel {
namespace {

constexpr std::array<std::uint8_t, 4> kHeader = {0xFF, 0xFF, 0xFD, 0x00};
// A packet's length field counts at most this much: longer is noise that happens to look like a header.
constexpr std::size_t kMaxLength = 1024;

// The CRC's table, built once: each byte's remainder after eight shifts.
std::array<std::uint16_t, 256> CrcTable() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    std::uint16_t crc = static_cast<std::uint16_t>(i << 8);
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x8005 : crc << 1);
    }
    table[i] = crc;
  }
  return table;
}

// The body (instruction and parameters, or the error and its parameters) with FD after every FF FF FD.
std::vector<std::uint8_t> Stuff(std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out;
  out.reserve(body.size() + 4);
  for (const std::uint8_t b : body) {
    out.push_back(b);
    const std::size_t n = out.size();
    if (n >= 3 && out[n - 3] == 0xFF && out[n - 2] == 0xFF && out[n - 1] == 0xFD) out.push_back(0xFD);
  }
  return out;
}

std::vector<std::uint8_t> Unstuff(std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out;
  out.reserve(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    out.push_back(body[i]);
    const std::size_t n = out.size();
    if (n >= 3 && out[n - 3] == 0xFF && out[n - 2] == 0xFF && out[n - 1] == 0xFD && i + 1 < body.size() &&
        body[i + 1] == 0xFD) {
      ++i;  // the stuffed FD
    }
  }
  return out;
}

void AppendLittle16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value & 0xFF));
  out.push_back(static_cast<std::uint8_t>(value >> 8));
}

}  // namespace

std::uint16_t Crc16(std::span<const std::uint8_t> bytes) {
  static const std::array<std::uint16_t, 256> kTable = CrcTable();
  std::uint16_t crc = 0;
  for (const std::uint8_t b : bytes) crc = static_cast<std::uint16_t>((crc << 8) ^ kTable[((crc >> 8) ^ b) & 0xFF]);
  return crc;
}

std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> parameters) {
  std::vector<std::uint8_t> body{static_cast<std::uint8_t>(instruction)};
  body.insert(body.end(), parameters.begin(), parameters.end());
  const std::vector<std::uint8_t> stuffed = Stuff(body);
  if (stuffed.size() + 2 > kMaxLength) throw std::invalid_argument("dynamixel: instruction packet too long");
  std::vector<std::uint8_t> packet(kHeader.begin(), kHeader.end());
  packet.push_back(id);
  AppendLittle16(packet, static_cast<std::uint16_t>(stuffed.size() + 2));
  packet.insert(packet.end(), stuffed.begin(), stuffed.end());
  AppendLittle16(packet, Crc16(packet));
  return packet;
}

std::vector<std::uint8_t> EncodePing(std::uint8_t id) { return EncodeInstruction(id, Instruction::kPing, {}); }

std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint16_t address, std::uint16_t length) {
  std::vector<std::uint8_t> parameters;
  AppendLittle16(parameters, address);
  AppendLittle16(parameters, length);
  return EncodeInstruction(id, Instruction::kRead, parameters);
}

std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> parameters;
  AppendLittle16(parameters, address);
  parameters.insert(parameters.end(), data.begin(), data.end());
  return EncodeInstruction(id, Instruction::kWrite, parameters);
}

std::vector<std::uint8_t> EncodeReboot(std::uint8_t id) { return EncodeInstruction(id, Instruction::kReboot, {}); }

void StatusParser::Push(std::span<const std::uint8_t> bytes, std::vector<StatusPacket>& out) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::size_t at = 0;
  while (buffer_.size() - at >= 7) {
    if (!std::equal(kHeader.begin(), kHeader.end(), buffer_.begin() + static_cast<std::ptrdiff_t>(at))) {
      ++at;
      continue;
    }
    const std::size_t length = buffer_[at + 5] | static_cast<std::size_t>(buffer_[at + 6]) << 8;
    if (length < 4 || length > kMaxLength) {  // a status packet has at least its instruction, error and CRC
      ++dropped_;
      ++at;
      continue;
    }
    if (buffer_.size() - at < 7 + length) break;
    const std::span<const std::uint8_t> packet(buffer_.data() + at, 7 + length);
    const std::uint16_t crc = static_cast<std::uint16_t>(packet[5 + length] | packet[6 + length] << 8);
    if (Crc16(packet.first(5 + length)) != crc || packet[7] != static_cast<std::uint8_t>(Instruction::kStatus)) {
      ++dropped_;
      ++at;  // resynchronise on the next header
      continue;
    }
    // Unstuffed from the instruction on, as it was stuffed; a status packet whose error byte went missing in it is
    // not one.
    std::vector<std::uint8_t> body = Unstuff(packet.subspan(7, length - 2));
    if (body.size() < 2) {
      ++dropped_;
      ++at;
      continue;
    }
    StatusPacket status;
    status.id = packet[4];
    status.error = body[1];
    status.parameters.assign(body.begin() + 2, body.end());
    out.push_back(std::move(status));
    at += 7 + length;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(at));
}

std::int32_t ReadInt32(std::span<const std::uint8_t> bytes, std::size_t at) {
  const std::uint32_t value = static_cast<std::uint32_t>(bytes[at]) | static_cast<std::uint32_t>(bytes[at + 1]) << 8 |
                              static_cast<std::uint32_t>(bytes[at + 2]) << 16 |
                              static_cast<std::uint32_t>(bytes[at + 3]) << 24;
  return static_cast<std::int32_t>(value);
}

void AppendInt32(std::vector<std::uint8_t>& out, std::int32_t value) {
  const auto v = static_cast<std::uint32_t>(value);
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

}  // namespace corridor::drivers::dynamixel
