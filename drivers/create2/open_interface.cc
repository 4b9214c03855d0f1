#include "drivers/create2/open_interface.h"

#include <algorithm>
#include <numbers>
#include <numeric>

#include "nav/demand.h"

namespace corridor::drivers::create2 {
namespace {

constexpr std::uint8_t kStreamHeader = 19;

std::uint16_t Big16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }

void PushBig16(std::vector<std::uint8_t>& out, int value) {
  const auto word = static_cast<std::uint16_t>(static_cast<std::int16_t>(value));
  out.push_back(static_cast<std::uint8_t>(word >> 8));
  out.push_back(static_cast<std::uint8_t>(word & 0xFF));
}

// Decodes one packet's data into `frame`.
void Decode(std::uint8_t id, const std::uint8_t* data, SensorFrame& frame, int& encoders) {
  switch (static_cast<Packet>(id)) {
    case Packet::kBumpsAndWheelDrops:
      frame.bump_right = (data[0] & 0x01) != 0;
      frame.bump_left = (data[0] & 0x02) != 0;
      frame.wheel_drop_right = (data[0] & 0x04) != 0;
      frame.wheel_drop_left = (data[0] & 0x08) != 0;
      break;
    case Packet::kCliffLeft:
    case Packet::kCliffFrontLeft:
    case Packet::kCliffFrontRight:
    case Packet::kCliffRight: frame.cliff = frame.cliff || data[0] != 0; break;
    case Packet::kChargingState: frame.charging_state = data[0]; break;
    case Packet::kVoltage: frame.voltage_v = Big16(data) / 1000.0; break;
    case Packet::kCurrent: frame.current_a = static_cast<std::int16_t>(Big16(data)) / 1000.0; break;
    case Packet::kBatteryCharge: frame.charge_ah = Big16(data) / 1000.0; break;
    case Packet::kBatteryCapacity: frame.capacity_ah = Big16(data) / 1000.0; break;
    case Packet::kChargingSources: frame.on_home_base = (data[0] & 0x02) != 0; break;
    case Packet::kOiMode: frame.oi_mode = data[0]; break;
    case Packet::kVirtualWall:
    case Packet::kCliffFrontLeftSignal: break;
    case Packet::kLeftEncoderCounts:
      frame.left_counts = Big16(data);
      ++encoders;
      break;
    case Packet::kRightEncoderCounts:
      frame.right_counts = Big16(data);
      ++encoders;
      break;
  }
}

// The frame in `body` (the packets: id, data, id, data...), or nothing when they do not fill it exactly.
std::optional<SensorFrame> DecodePackets(std::span<const std::uint8_t> body) {
  SensorFrame frame;
  int encoders = 0;
  std::size_t at = 0;
  while (at < body.size()) {
    const std::optional<std::size_t> size = PacketSize(body[at]);
    if (!size || at + 1 + *size > body.size()) return std::nullopt;
    Decode(body[at], body.data() + at + 1, frame, encoders);
    at += 1 + *size;
  }
  frame.has_encoders = encoders == 2;
  return frame;
}

}  // namespace

std::optional<std::size_t> PacketSize(std::uint8_t id) {
  switch (static_cast<Packet>(id)) {
    case Packet::kBumpsAndWheelDrops:
    case Packet::kCliffLeft:
    case Packet::kCliffFrontLeft:
    case Packet::kCliffFrontRight:
    case Packet::kCliffRight:
    case Packet::kChargingState:
    case Packet::kChargingSources:
    case Packet::kVirtualWall:
    case Packet::kOiMode: return 1;
    case Packet::kCliffFrontLeftSignal:
    case Packet::kVoltage:
    case Packet::kCurrent:
    case Packet::kBatteryCharge:
    case Packet::kBatteryCapacity:
    case Packet::kLeftEncoderCounts:
    case Packet::kRightEncoderCounts: return 2;
  }
  return std::nullopt;
}

const std::vector<Packet>& StreamedPackets() {
  static const std::vector<Packet> kPackets = {
      Packet::kBumpsAndWheelDrops, Packet::kCliffLeft,         Packet::kCliffFrontLeft,  Packet::kCliffFrontRight,
      Packet::kCliffRight,         Packet::kChargingState,     Packet::kVoltage,         Packet::kCurrent,
      Packet::kBatteryCharge,      Packet::kBatteryCapacity,   Packet::kChargingSources, Packet::kOiMode,
      Packet::kLeftEncoderCounts,  Packet::kRightEncoderCounts};
  return kPackets;
}

std::vector<std::uint8_t> EncodeStart() { return {static_cast<std::uint8_t>(Opcode::kStart)}; }
std::vector<std::uint8_t> EncodeSafe() { return {static_cast<std::uint8_t>(Opcode::kSafe)}; }
std::vector<std::uint8_t> EncodeStop() { return {static_cast<std::uint8_t>(Opcode::kStop)}; }

std::vector<std::uint8_t> EncodeDriveDirect(int left_mmps, int right_mmps) {
  std::vector<std::uint8_t> out = {static_cast<std::uint8_t>(Opcode::kDriveDirect)};
  PushBig16(out, std::clamp(right_mmps, -500, 500));
  PushBig16(out, std::clamp(left_mmps, -500, 500));
  return out;
}

std::vector<std::uint8_t> EncodeStream(std::span<const Packet> packets) {
  DEMAND(packets.size() <= 255);  // the driver asks for a handful of packets
  std::vector<std::uint8_t> out = {static_cast<std::uint8_t>(Opcode::kStream),
                                   static_cast<std::uint8_t>(packets.size())};
  for (const Packet p : packets) out.push_back(static_cast<std::uint8_t>(p));
  return out;
}

std::vector<std::uint8_t> EncodePauseStream(bool resume) {
  return {static_cast<std::uint8_t>(Opcode::kPauseResumeStream), static_cast<std::uint8_t>(resume ? 1 : 0)};
}

void StreamParser::Push(std::span<const std::uint8_t> bytes, std::vector<SensorFrame>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  std::size_t at = 0;
  while (true) {
    while (at < pending_.size() && pending_[at] != kStreamHeader) ++at;
    if (pending_.size() - at < 2) break;
    const std::size_t count = pending_[at + 1];
    if (count == 0 || count > kMaxFrameBytes || (pending_.size() - at > 2 && !PacketSize(pending_[at + 2]))) {
      ++at;  // noise that looked like a header
      continue;
    }
    const std::size_t whole = 2 + count + 1;  // header, count, packets, checksum
    if (pending_.size() - at < whole) break;
    const auto first = pending_.begin() + static_cast<std::ptrdiff_t>(at);
    const auto sum = std::accumulate(first, first + static_cast<std::ptrdiff_t>(whole), 0u);
    const std::optional<SensorFrame> frame =
        (sum & 0xFF) == 0 ? DecodePackets(std::span<const std::uint8_t>(pending_).subspan(at + 2, count))
                          : std::nullopt;
    if (!frame) {
      ++dropped_;
      ++at;  // a header byte that began no frame: look for the next
      continue;
    }
    out.push_back(*frame);
    at += whole;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
  DEMAND(pending_.size() < 2 + kMaxFrameBytes + 1);  // at most a frame in waiting: noise never piles up
}

}  // namespace corridor::drivers::create2
