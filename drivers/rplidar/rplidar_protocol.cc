#include "drivers/rplidar/rplidar_protocol.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::drivers::rplidar {
namespace {

// Nodes in a row that must pass their check bits, each turning on clockwise by less than kMaxStepDeg, before nodes are
// taken at an alignment (a misaligned one passes the check bits one time in four). Devices measure every degree or
// finer.
constexpr std::size_t kAlignNodes = 3;
constexpr double kMaxStepDeg = 10.0;

std::uint16_t Little16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }

}  // namespace

std::vector<std::uint8_t> EncodeRequest(Command command, std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out = {kStartFlag1, static_cast<std::uint8_t>(command)};
  if (payload.empty()) return out;
  if (payload.size() > 255) throw std::invalid_argument("rplidar: a request's payload is at most 255 bytes");
  out.push_back(static_cast<std::uint8_t>(payload.size()));
  out.insert(out.end(), payload.begin(), payload.end());
  std::uint8_t checksum = 0;
  for (const std::uint8_t b : out) checksum ^= b;
  out.push_back(checksum);
  return out;
}

std::array<std::uint8_t, kDescriptorBytes> EncodeDescriptor(const Descriptor& descriptor) {
  const std::uint32_t word = (descriptor.length & 0x3FFFFFFFu) | (descriptor.repeated ? 1u << 30 : 0u);
  return {kStartFlag1,
          kStartFlag2,
          static_cast<std::uint8_t>(word),
          static_cast<std::uint8_t>(word >> 8),
          static_cast<std::uint8_t>(word >> 16),
          static_cast<std::uint8_t>(word >> 24),
          descriptor.type};
}

std::optional<Descriptor> DecodeDescriptor(std::span<const std::uint8_t, kDescriptorBytes> bytes) {
  if (bytes[0] != kStartFlag1 || bytes[1] != kStartFlag2) return std::nullopt;
  const std::uint32_t word = static_cast<std::uint32_t>(bytes[2]) | static_cast<std::uint32_t>(bytes[3]) << 8 |
                             static_cast<std::uint32_t>(bytes[4]) << 16 | static_cast<std::uint32_t>(bytes[5]) << 24;
  return Descriptor{word & 0x3FFFFFFFu, (word >> 30) == 1u, bytes[6]};
}

DeviceInfo DecodeInfo(std::span<const std::uint8_t, kInfoBytes> bytes) {
  DeviceInfo info;
  info.model = bytes[0];
  info.firmware_minor = bytes[1];
  info.firmware_major = bytes[2];
  info.hardware = bytes[3];
  static constexpr char kHex[] = "0123456789ABCDEF";
  for (std::size_t i = 4; i < kInfoBytes; ++i) {
    info.serial += kHex[bytes[i] >> 4];
    info.serial += kHex[bytes[i] & 0x0F];
  }
  return info;
}

DeviceHealth DecodeHealth(std::span<const std::uint8_t, kHealthBytes> bytes) {
  return DeviceHealth{bytes[0], Little16(&bytes[1])};
}

std::array<std::uint8_t, kNodeBytes> EncodeNode(const Node& node) {
  const int quality = std::clamp(node.quality, 0, 63);
  const double wrapped = std::fmod(std::fmod(node.angle_deg, 360.0) + 360.0, 360.0);
  const auto angle_q6 = static_cast<std::uint16_t>(std::lround(wrapped * 64.0) & 0x7FFF);
  const auto distance_q2 =
      static_cast<std::uint16_t>(std::clamp<long>(std::lround(node.distance_m * 4000.0), 0, 0xFFFF));
  return {static_cast<std::uint8_t>(quality << 2 | (node.start ? 0x01 : 0x02)),
          static_cast<std::uint8_t>((angle_q6 & 0x7F) << 1 | 0x01), static_cast<std::uint8_t>(angle_q6 >> 7),
          static_cast<std::uint8_t>(distance_q2), static_cast<std::uint8_t>(distance_q2 >> 8)};
}

std::optional<Node> DecodeNode(std::span<const std::uint8_t, kNodeBytes> bytes) {
  const bool start = (bytes[0] & 0x01) != 0;
  const bool not_start = (bytes[0] & 0x02) != 0;
  if (start == not_start || (bytes[1] & 0x01) == 0) return std::nullopt;
  Node node;
  node.start = start;
  node.quality = bytes[0] >> 2;
  node.angle_deg = static_cast<double>((bytes[1] >> 1) | (bytes[2] << 7)) / 64.0;
  node.distance_m = static_cast<double>(Little16(&bytes[3])) / 4000.0;
  return node;
}

void NodeStream::Push(std::span<const std::uint8_t> bytes, std::vector<Node>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  const auto node_at = [&](std::size_t at) {
    return DecodeNode(std::span<const std::uint8_t, kNodeBytes>(pending_.data() + at, kNodeBytes));
  };
  // Whether `node` may follow a node at `before` (degrees) in a revolution.
  const auto follows = [](const std::optional<Node>& node, std::optional<double> before) {
    return node && node->angle_deg < 360.0 &&
           (!before || std::fmod(node->angle_deg - *before + 360.0, 360.0) < kMaxStepDeg);
  };
  std::size_t at = 0;
  while (pending_.size() - at >= kNodeBytes) {
    if (!in_sync_) {
      if (pending_.size() - at < kAlignNodes * kNodeBytes) break;  // too few bytes yet to judge this alignment
      std::optional<double> last;
      std::size_t run = 0;
      for (; run < kAlignNodes; ++run) {
        const std::optional<Node> node = node_at(at + run * kNodeBytes);
        if (!follows(node, last)) break;
        last = node->angle_deg;
      }
      if (run < kAlignNodes) {
        ++at;
        ++skipped_;
        continue;
      }
      in_sync_ = true;
      last_angle_deg_.reset();
    }
    const std::optional<Node> node = node_at(at);
    if (!follows(node, last_angle_deg_)) {
      in_sync_ = false;
      ++at;
      ++skipped_;
      continue;
    }
    out.push_back(*node);
    last_angle_deg_ = node->angle_deg;
    at += kNodeBytes;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
}

std::vector<std::uint8_t> EncodeExpressScanRequest() {
  const std::array<std::uint8_t, 5> payload = {0, 0, 0, 0, 0};  // working mode 0 (legacy capsules), reserved
  return EncodeRequest(Command::kExpressScan, payload);
}

namespace {

constexpr std::uint8_t kCapsuleSync1 = 0xA;
constexpr std::uint8_t kCapsuleSync2 = 0x5;
constexpr std::size_t kCabinBytes = 5;

std::uint8_t CapsuleChecksum(const std::uint8_t* bytes) {
  std::uint8_t checksum = 0;
  for (std::size_t i = 2; i < kCapsuleBytes; ++i) checksum ^= bytes[i];
  return checksum;
}

}  // namespace

std::array<std::uint8_t, kCapsuleBytes> EncodeCapsule(const Capsule& capsule) {
  std::array<std::uint8_t, kCapsuleBytes> out{};
  const double wrapped = std::fmod(std::fmod(capsule.start_angle_deg, 360.0) + 360.0, 360.0);
  const auto angle_q6 = static_cast<std::uint16_t>(std::lround(wrapped * 64.0) % (360 * 64));
  const std::uint16_t angle_word = angle_q6 | (capsule.start ? 0x8000 : 0);
  out[2] = static_cast<std::uint8_t>(angle_word);
  out[3] = static_cast<std::uint8_t>(angle_word >> 8);
  for (std::size_t cabin = 0; cabin < kCapsuleSamples / 2; ++cabin) {
    std::uint8_t* c = &out[4 + cabin * kCabinBytes];
    for (std::size_t j = 0; j < 2; ++j) {
      const std::size_t k = cabin * 2 + j;
      const auto mm =
          static_cast<std::uint16_t>(std::clamp<long>(std::lround(capsule.distance_m[k] * 1000.0), 0, 0x3FFF));
      const auto correction =  // 6-bit two's complement of 1/8 degree
          static_cast<std::uint8_t>(std::clamp<long>(std::lround(capsule.correction_deg[k] * 8.0), -32, 31) & 0x3F);
      const std::uint16_t word = static_cast<std::uint16_t>(mm << 2 | correction >> 4);
      c[j * 2] = static_cast<std::uint8_t>(word);
      c[j * 2 + 1] = static_cast<std::uint8_t>(word >> 8);
      c[4] |= static_cast<std::uint8_t>((correction & 0x0F) << (j * 4));
    }
  }
  const std::uint8_t checksum = CapsuleChecksum(out.data());
  out[0] = static_cast<std::uint8_t>(kCapsuleSync1 << 4 | (checksum & 0x0F));
  out[1] = static_cast<std::uint8_t>(kCapsuleSync2 << 4 | checksum >> 4);
  return out;
}

std::optional<Capsule> DecodeCapsule(std::span<const std::uint8_t, kCapsuleBytes> bytes) {
  if (bytes[0] >> 4 != kCapsuleSync1 || bytes[1] >> 4 != kCapsuleSync2) return std::nullopt;
  const auto checksum = static_cast<std::uint8_t>((bytes[0] & 0x0F) | (bytes[1] & 0x0F) << 4);
  if (checksum != CapsuleChecksum(bytes.data())) return std::nullopt;
  const std::uint16_t angle_word = Little16(&bytes[2]);
  const int angle_q6 = angle_word & 0x7FFF;
  if (angle_q6 >= 360 * 64) return std::nullopt;
  Capsule capsule;
  capsule.start = (angle_word & 0x8000) != 0;
  capsule.start_angle_deg = angle_q6 / 64.0;
  for (std::size_t cabin = 0; cabin < kCapsuleSamples / 2; ++cabin) {
    const std::uint8_t* c = &bytes[4 + cabin * kCabinBytes];
    for (std::size_t j = 0; j < 2; ++j) {
      const std::size_t k = cabin * 2 + j;
      const std::uint16_t word = Little16(c + j * 2);
      const int low = (c[4] >> (j * 4)) & 0x0F;
      int correction = (word & 0x3) << 4 | low;
      if (correction & 0x20) correction -= 64;  // the top bit is the sign
      capsule.distance_m[k] = (word >> 2) / 1000.0;
      capsule.correction_deg[k] = correction / 8.0;
    }
  }
  return capsule;
}

void CapsuleSamples(const Capsule& capsule, double next_start_angle_deg, std::vector<SweepPoint>& out) {
  // AngleDiff: the way on to the next capsule's start, through forward when it is smaller.
  double span = next_start_angle_deg - capsule.start_angle_deg;
  if (span < 0.0) span += 360.0;
  const double step = span / static_cast<double>(kCapsuleSamples);
  for (std::size_t k = 0; k < kCapsuleSamples; ++k) {
    const double place = capsule.start_angle_deg + step * static_cast<double>(k);
    const double before = place - step;
    SweepPoint point;
    point.start = std::floor(place / 360.0) > std::floor(before / 360.0);
    point.distance_m = capsule.distance_m[k];
    point.quality = point.distance_m > 0.0 ? 1 : 0;  // capsules carry no quality: a distance is a measurement
    const double angle = place - capsule.correction_deg[k];
    point.angle_deg = std::fmod(std::fmod(angle, 360.0) + 360.0, 360.0);
    out.push_back(point);
  }
}

void CapsuleStream::Push(std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  std::size_t at = 0;
  while (pending_.size() - at >= kCapsuleBytes) {
    const std::optional<Capsule> capsule =
        DecodeCapsule(std::span<const std::uint8_t, kCapsuleBytes>(pending_.data() + at, kCapsuleBytes));
    if (!capsule) {
      previous_.reset();  // the next capsule taken may not be the one after it
      ++at;
      ++skipped_;
      continue;
    }
    ++capsules_;
    if (previous_ && !capsule->start) CapsuleSamples(*previous_, capsule->start_angle_deg, out);
    previous_ = capsule;
    at += kCapsuleBytes;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
}

}  // namespace corridor::drivers::rplidar
