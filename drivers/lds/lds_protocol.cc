#include "drivers/lds/lds_protocol.h"

#include <algorithm>
#include <cmath>

namespace corridor::drivers::lds {
namespace {

std::uint16_t Little16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }

}  // namespace

std::uint8_t Crc8(std::span<const std::uint8_t> bytes) {
  constexpr std::uint8_t kPolynomial = 0x4D;
  std::uint8_t crc = 0;
  for (const std::uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ kPolynomial : crc << 1);
    }
  }
  return crc;
}

std::optional<Ld08Packet> DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes> bytes) {
  if (bytes[0] != kLd08Header || bytes[1] != kLd08VerLen) return std::nullopt;
  if (Crc8(bytes.first(kLd08PacketBytes - 1)) != bytes[kLd08PacketBytes - 1]) return std::nullopt;
  Ld08Packet packet;
  packet.speed_deg_s = Little16(&bytes[2]);
  packet.start_deg = Little16(&bytes[4]) / 100.0;
  for (int i = 0; i < kLd08Points; ++i) {
    const std::uint8_t* point = &bytes[6 + 3 * static_cast<std::size_t>(i)];
    packet.distance_mm[static_cast<std::size_t>(i)] = Little16(point);
    packet.intensity[static_cast<std::size_t>(i)] = point[2];
  }
  packet.end_deg = Little16(&bytes[42]) / 100.0;
  packet.timestamp_ms = Little16(&bytes[44]);
  if (packet.start_deg >= 360.0 || packet.end_deg >= 360.0) return std::nullopt;
  return packet;
}

double Ld08Angle(const Ld08Packet& packet, int i) {
  const double end = packet.end_deg < packet.start_deg ? packet.end_deg + 360.0 : packet.end_deg;
  const double angle = packet.start_deg + i * (end - packet.start_deg) / (kLd08Points - 1);
  return angle >= 360.0 ? angle - 360.0 : angle;
}

std::optional<LfcdPacket> DecodeLfcd(std::span<const std::uint8_t, kLfcdPacketBytes> bytes) {
  if (bytes[0] != kLfcdStart || bytes[1] < kLfcdFirstIndex || bytes[1] >= kLfcdFirstIndex + kLfcdPackets) {
    return std::nullopt;
  }
  LfcdPacket packet;
  packet.index = bytes[1] - kLfcdFirstIndex;
  packet.speed = Little16(&bytes[2]);
  for (int i = 0; i < kLfcdReadings; ++i) {
    const std::uint8_t* reading = &bytes[4 + 6 * static_cast<std::size_t>(i)];
    packet.intensity[static_cast<std::size_t>(i)] = Little16(reading);
    packet.distance_mm[static_cast<std::size_t>(i)] = Little16(reading + 2);
  }
  return packet;
}

void PacketStream::Emit(double angle_deg, std::uint16_t distance_mm, int quality, std::vector<SweepPoint>& out) {
  SweepPoint point;
  point.start = last_angle_deg_ && angle_deg < *last_angle_deg_;
  point.quality = distance_mm == 0 ? 0 : std::max(1, quality);  // a distance of 0 is no measurement
  point.angle_deg = angle_deg;
  point.distance_m = distance_mm / 1000.0;
  last_angle_deg_ = angle_deg;
  out.push_back(point);
}

bool PacketStream::TakeLd08(std::size_t at, std::vector<SweepPoint>& out) {
  const std::optional<Ld08Packet> packet =
      DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes>(pending_.data() + at, kLd08PacketBytes));
  if (!packet) return false;
  speed_deg_s_ = packet->speed_deg_s;
  for (int i = 0; i < kLd08Points; ++i) {
    const auto k = static_cast<std::size_t>(i);
    Emit(Ld08Angle(*packet, i), packet->distance_mm[k], packet->intensity[k], out);
  }
  return true;
}

bool PacketStream::TakeLfcd(std::size_t at, bool& wait, std::vector<SweepPoint>& out) {
  const auto packet_at = [&](std::size_t from) {
    return DecodeLfcd(std::span<const std::uint8_t, kLfcdPacketBytes>(pending_.data() + from, kLfcdPacketBytes));
  };
  const std::optional<LfcdPacket> packet = packet_at(at);
  if (!packet) return false;
  // The next packet's start and index must follow: a byte lost or added inside this one shows there.
  if (pending_.size() - at < kLfcdPacketBytes + 2) {
    wait = true;
    return false;
  }
  const std::uint8_t* next = pending_.data() + at + kLfcdPacketBytes;
  if (next[0] != kLfcdStart || next[1] != kLfcdFirstIndex + (packet->index + 1) % kLfcdPackets) return false;
  for (int i = 0; i < kLfcdReadings; ++i) {
    const auto k = static_cast<std::size_t>(i);
    Emit(6.0 * packet->index + i, packet->distance_mm[k], std::min<int>(packet->intensity[k], 0xFFFF), out);
  }
  return true;
}

void PacketStream::Push(std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  const std::size_t size = model_ == Model::kLds02 ? kLd08PacketBytes : kLfcdPacketBytes;
  std::size_t at = 0;
  while (pending_.size() - at >= size) {
    bool wait = false;
    const bool taken = model_ == Model::kLds02 ? TakeLd08(at, out) : TakeLfcd(at, wait, out);
    if (wait) break;
    if (taken) {
      ++packets_;
      at += size;
    } else {
      ++skipped_;
      ++at;
    }
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
}

}  // namespace corridor::drivers::lds
