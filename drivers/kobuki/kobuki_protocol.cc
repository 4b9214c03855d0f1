#include "drivers/kobuki/kobuki_protocol.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::drivers::kobuki {
namespace {

constexpr std::size_t kBasicSensorDataBytes = 15;
constexpr std::size_t kInertialSensorBytes = 7;
// The Charger byte's bits: charging (6, 22), and the adapter rather than the dock (18, 22).
constexpr int kChargingBit = 0x04;
constexpr int kConnectedBit = 0x02;
constexpr int kAdapterBit = 0x10;

std::uint16_t Little16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | p[1] << 8); }

void PushLittle16(std::vector<std::uint8_t>& out, int value) {
  const auto word = static_cast<std::uint16_t>(static_cast<std::int16_t>(value));
  out.push_back(static_cast<std::uint8_t>(word & 0xFF));
  out.push_back(static_cast<std::uint8_t>(word >> 8));
}

SensorData DecodeSensorData(const std::uint8_t* d) {
  SensorData s;
  s.timestamp_ms = Little16(d);
  s.bump_right = (d[2] & 0x01) != 0;
  s.bump_centre = (d[2] & 0x02) != 0;
  s.bump_left = (d[2] & 0x04) != 0;
  s.wheel_drop_right = (d[3] & 0x01) != 0;
  s.wheel_drop_left = (d[3] & 0x02) != 0;
  s.cliff = (d[4] & 0x07) != 0;
  s.left_counts = Little16(d + 5);
  s.right_counts = Little16(d + 7);
  // d[9], d[10]: the wheels' PWM; d[11]: the buttons.
  s.charger = d[12];
  s.battery_v = d[13] * 0.1;
  s.over_current = (d[14] & 0x03) != 0;
  return s;
}

// The sub-payloads of a packet whose checksum held, or nothing when they do not fill it exactly.
std::optional<FeedbackPacket> DecodePayload(std::span<const std::uint8_t> payload) {
  FeedbackPacket packet;
  std::size_t at = 0;
  while (at < payload.size()) {
    if (at + 2 > payload.size()) return std::nullopt;
    const std::uint8_t id = payload[at];
    const std::size_t length = payload[at + 1];
    const std::uint8_t* data = payload.data() + at + 2;
    if (at + 2 + length > payload.size()) return std::nullopt;
    if (id == static_cast<std::uint8_t>(Feedback::kBasicSensorData)) {
      if (length != kBasicSensorDataBytes) return std::nullopt;
      packet.sensors = DecodeSensorData(data);
    } else if (id == static_cast<std::uint8_t>(Feedback::kInertialSensor)) {
      if (length != kInertialSensorBytes) return std::nullopt;
      // Its angle in hundredths of a degree.
      packet.heading_rad = static_cast<std::int16_t>(Little16(data)) * 0.01 * std::numbers::pi / 180.0;
    }
    at += 2 + length;
  }
  return packet;
}

}  // namespace

std::vector<std::uint8_t> EncodePacket(std::span<const std::uint8_t> payload) {
  if (payload.size() > std::numeric_limits<std::uint8_t>::max()) {
    throw std::invalid_argument("kobuki: a payload is at most 255 bytes");
  }
  std::vector<std::uint8_t> out{kHeader0, kHeader1, static_cast<std::uint8_t>(payload.size())};
  std::uint8_t checksum = out[2];
  for (const std::uint8_t b : payload) {
    out.push_back(b);
    checksum ^= b;
  }
  out.push_back(checksum);
  return out;
}

std::vector<std::uint8_t> EncodeBaseControl(const BaseControl& command) {
  std::vector<std::uint8_t> payload{static_cast<std::uint8_t>(Command::kBaseControl), 4};
  PushLittle16(payload, command.speed_mmps);
  PushLittle16(payload, command.radius_mm);
  return EncodePacket(payload);
}

BaseControl ToBaseControl(const nav::Twist2& twist, double track_m) {
  const auto mm = [](double m) { return static_cast<int>(std::clamp(std::lround(m * 1000.0), -32768L, 32767L)); };
  constexpr double kStillRps = 1e-4;
  if (std::abs(twist.angular_rps) < kStillRps) return {mm(twist.linear_mps), 0};
  const double radius_m = twist.linear_mps / twist.angular_rps;
  // Turning on the spot, or about a point within a millimetre of the centre: each wheel at the turn's speed.
  if (std::abs(radius_m) < 0.0015) return {mm(twist.angular_rps * track_m / 2.0), 1};
  // So wide an arc that its radius does not fit: straight on.
  if (std::abs(radius_m) > 32.767) return {mm(twist.linear_mps), 0};
  // The outer wheel runs half a track farther from the arc's centre than the robot's centre does.
  const double outer_mps = twist.angular_rps * (radius_m + std::copysign(track_m / 2.0, radius_m));
  return {mm(outer_mps), mm(radius_m)};
}

bool Charging(int charger) { return (charger & kChargingBit) != 0; }

bool OnDock(int charger) { return (charger & kConnectedBit) != 0 && (charger & kAdapterBit) == 0; }

void PacketParser::Push(std::span<const std::uint8_t> bytes, std::vector<FeedbackPacket>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  std::size_t at = 0;
  while (true) {
    // The next header.
    std::size_t start = at;
    while (start + 1 < pending_.size() && !(pending_[start] == kHeader0 && pending_[start + 1] == kHeader1)) ++start;
    if (start + 1 >= pending_.size()) {
      // Keep a last 0xAA: it may begin the next header.
      const std::size_t keep = pending_.size() > at && pending_.back() == kHeader0 ? 1 : 0;
      skipped_ += pending_.size() - at - keep;
      at = pending_.size() - keep;
      break;
    }
    skipped_ += start - at;
    at = start;
    if (at + 3 > pending_.size()) break;  // the length is still to come
    const std::size_t length = pending_[at + 2];
    if (at + 3 + length + 1 > pending_.size()) break;  // the rest is still to come
    std::uint8_t checksum = pending_[at + 2];
    for (std::size_t i = 0; i < length; ++i) checksum ^= pending_[at + 3 + i];
    std::optional<FeedbackPacket> packet;
    if (checksum == pending_[at + 3 + length]) {
      packet = DecodePayload(std::span<const std::uint8_t>(pending_.data() + at + 3, length));
    }
    if (!packet) {
      ++dropped_;
      at += 1;  // a header inside what looked like a packet may be the real one
      continue;
    }
    out.push_back(*packet);
    at += 3 + length + 1;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
}

}  // namespace corridor::drivers::kobuki
