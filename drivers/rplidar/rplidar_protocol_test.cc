// The RPLIDAR protocol's frames byte for byte as Slamtec's "RPLIDAR Interface Protocol and Application Notes" gives
// them (standard nodes and express capsules), and the byte stream's faults a serial port shows: noise before the first
// frame, a byte lost, a bad check bit or checksum.
#include "drivers/rplidar/rplidar_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace corridor::drivers::rplidar {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(RplidarProtocolTest, RequestsAreTheStartFlagAndTheCommandWithAChecksummedPayload) {
  EXPECT_EQ(EncodeRequest(Command::kScan), (Bytes{0xA5, 0x20}));
  EXPECT_EQ(EncodeRequest(Command::kStop), (Bytes{0xA5, 0x25}));
  EXPECT_EQ(EncodeRequest(Command::kGetHealth), (Bytes{0xA5, 0x52}));
  // The A2's motor at duty 660: the payload 0x0294 little endian, then the XOR of every byte before it.
  const Bytes pwm = {0x94, 0x02};
  EXPECT_EQ(EncodeRequest(Command::kSetMotorPwm, pwm), (Bytes{0xA5, 0xF0, 0x02, 0x94, 0x02, 0xC1}));
}

TEST(RplidarProtocolTest, DescriptorsCarryTheLengthTheSendModeAndTheType) {
  const std::array<std::uint8_t, kDescriptorBytes> scan = {0xA5, 0x5A, 0x05, 0x00, 0x00, 0x40, 0x81};
  const std::optional<Descriptor> d = DecodeDescriptor(scan);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->length, 5u);
  EXPECT_TRUE(d->repeated);
  EXPECT_EQ(d->type, static_cast<std::uint8_t>(DataType::kScan));
  EXPECT_EQ(EncodeDescriptor(*d), scan);
  const std::array<std::uint8_t, kDescriptorBytes> info = {0xA5, 0x5A, 0x14, 0x00, 0x00, 0x00, 0x04};
  ASSERT_TRUE(DecodeDescriptor(info));
  EXPECT_EQ(DecodeDescriptor(info)->length, 20u);
  EXPECT_FALSE(DecodeDescriptor(info)->repeated);
  const std::array<std::uint8_t, kDescriptorBytes> garbage = {0xA5, 0x00, 0x05, 0x00, 0x00, 0x40, 0x81};
  EXPECT_FALSE(DecodeDescriptor(garbage));
}

TEST(RplidarProtocolTest, InfoAndHealthAreDecoded) {
  const std::array<std::uint8_t, kInfoBytes> info = {0x18, 0x1D, 0x01, 0x07, 0xDE, 0xAD, 0xBE, 0xEF, 0x00, 0x01,
                                                     0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B};
  const DeviceInfo i = DecodeInfo(info);
  EXPECT_EQ(i.model, 0x18);
  EXPECT_EQ(i.firmware_major, 1);
  EXPECT_EQ(i.firmware_minor, 29);
  EXPECT_EQ(i.hardware, 7);
  EXPECT_EQ(i.serial, "DEADBEEF000102030405060708090A0B");
  const std::array<std::uint8_t, kHealthBytes> health = {0x02, 0x34, 0x12};
  EXPECT_EQ(DecodeHealth(health).status, 2);
  EXPECT_EQ(DecodeHealth(health).error_code, 0x1234);
}

TEST(RplidarProtocolTest, ANodeIsQualityAndStartFlagsAngleInSixtyFourthsAndDistanceInQuarterMillimetres) {
  // Quality 15, the first of a revolution, 90 degrees, 1.5 m: 15 << 2 | S=1 | !S=0; 90 x 64 = 0x1680 over the check
  // bit; 1500 mm x 4 = 0x1770.
  const std::array<std::uint8_t, kNodeBytes> bytes = {0x3D, 0x01, 0x2D, 0x70, 0x17};
  const std::optional<Node> node = DecodeNode(bytes);
  ASSERT_TRUE(node);
  EXPECT_TRUE(node->start);
  EXPECT_EQ(node->quality, 15);
  EXPECT_DOUBLE_EQ(node->angle_deg, 90.0);
  EXPECT_DOUBLE_EQ(node->distance_m, 1.5);
  EXPECT_EQ(EncodeNode(*node), bytes);
  // The start flag and its inverse equal, or the check bit clear: not a node.
  EXPECT_FALSE(DecodeNode(std::array<std::uint8_t, kNodeBytes>{0x3F, 0x01, 0x2D, 0x70, 0x17}));
  EXPECT_FALSE(DecodeNode(std::array<std::uint8_t, kNodeBytes>{0x3C, 0x01, 0x2D, 0x70, 0x17}));
  EXPECT_FALSE(DecodeNode(std::array<std::uint8_t, kNodeBytes>{0x3D, 0x00, 0x2D, 0x70, 0x17}));
}

// A revolution of `count` nodes, clockwise from 0, each at `range(angle_deg)`.
Bytes Revolution(int count, double (*range)(double)) {
  Bytes out;
  for (int i = 0; i < count; ++i) {
    const double angle = 360.0 * i / count;
    const auto node = EncodeNode(Node{i == 0, 40, angle, range(angle)});
    out.insert(out.end(), node.begin(), node.end());
  }
  return out;
}

double RangeOf(double angle_deg) { return 1.0 + angle_deg / 360.0; }

TEST(RplidarProtocolTest, TheStreamRecoversFromNoiseAndALostByteAndLosesOnlyTheNodesTheyTouch) {
  const Bytes clean = Revolution(100, RangeOf);
  // Noise before the first node, a byte lost from the 40th, pieces of one to seven bytes as a serial port reads them.
  Bytes bytes = {0x00, 0xFF, 0x13, 0x37, 0x42};
  bytes.insert(bytes.end(), clean.begin(), clean.end());
  bytes.erase(bytes.begin() + 5 + 40 * kNodeBytes + 2);
  NodeStream stream;
  std::vector<Node> nodes;
  for (std::size_t at = 0, piece = 1; at < bytes.size(); at += piece, piece = piece % 7 + 1) {
    stream.Push(std::span<const std::uint8_t>(bytes).subspan(at, std::min(piece, bytes.size() - at)), nodes);
  }
  EXPECT_GT(stream.skipped_bytes(), 0u);
  EXPECT_GE(nodes.size(), 90u);
  EXPECT_LT(nodes.size(), 100u);
  // What comes out is what was sent: each node's range still matches its angle.
  for (const Node& n : nodes) EXPECT_NEAR(n.distance_m, RangeOf(n.angle_deg), 1e-3) << n.angle_deg;
  EXPECT_NEAR(nodes.back().angle_deg, 360.0 * 99 / 100, 1.0 / 128.0);  // 1/64 degree steps
}

TEST(RplidarProtocolTest, SweepsBecomeCounterClockwiseScansFromTheStartFlagOn) {
  SweepOptions options;
  options.bins = 360;
  SweepAssembler sweeps(options);
  const auto feed = [&](const Bytes& bytes, TimeNs stamp) {
    NodeStream stream;
    std::vector<Node> nodes;
    stream.Push(bytes, nodes);
    std::optional<LaserScan> last;
    for (const Node& n : nodes) {
      if (auto scan = sweeps.Add(n, stamp)) last = std::move(scan);
    }
    return last;
  };
  // Spinning up: a short revolution, then the first whole one, ended by the next start flag.
  EXPECT_FALSE(feed(Revolution(20, RangeOf), 1));
  EXPECT_FALSE(feed(Revolution(360, RangeOf), 2)) << "the short revolution is not a scan";
  const std::optional<LaserScan> scan = feed(Revolution(360, RangeOf), 3);
  ASSERT_TRUE(scan);
  ASSERT_EQ(scan->ranges.size(), 360u);
  EXPECT_EQ(scan->stamp_ns, 3);
  EXPECT_DOUBLE_EQ(scan->angle_min_rad, -std::numbers::pi);
  // 90 degrees clockwise (the robot's right) is -90 degrees in the scan; 90 counter-clockwise is the device's 270.
  const auto at = [&](double deg) {
    const double a = deg * std::numbers::pi / 180.0;
    return scan
        ->ranges[static_cast<std::size_t>(std::lround((a - scan->angle_min_rad) / scan->angle_increment_rad)) % 360];
  };
  EXPECT_NEAR(at(-90.0), RangeOf(90.0), 1e-3);
  EXPECT_NEAR(at(90.0), RangeOf(270.0), 1e-3);
  EXPECT_NEAR(at(0.0), RangeOf(0.0), 1e-3);
}

TEST(RplidarProtocolTest, MeasurementsOfNoQualityOrOutOfRangeAreNotInTheScan) {
  SweepOptions options;
  options.bins = 8;
  options.min_points = 1;
  SweepAssembler sweeps(options);
  EXPECT_FALSE(sweeps.Add(Node{true, 40, 0.0, 2.0}, 1));
  sweeps.Add(Node{false, 0, 45.0, 2.0}, 1);     // the device saw nothing
  sweeps.Add(Node{false, 40, 90.0, 0.05}, 1);   // inside the housing
  sweeps.Add(Node{false, 40, 135.0, 30.0}, 1);  // past the range
  sweeps.Add(Node{false, 40, 180.0, 3.0}, 1);
  const std::optional<LaserScan> scan = sweeps.Add(Node{true, 40, 0.0, 2.0}, 2);
  ASSERT_TRUE(scan);
  int finite = 0;
  for (const float r : scan->ranges) finite += std::isfinite(r) ? 1 : 0;
  EXPECT_EQ(finite, 2);
  EXPECT_FLOAT_EQ(scan->ranges[4], 2.0f);  // forward: -pi + 4 x 45 degrees
  EXPECT_FLOAT_EQ(scan->ranges[0], 3.0f);  // behind
  EXPECT_THROW(SweepAssembler(SweepOptions{.bins = 2}), std::invalid_argument);
}

TEST(RplidarProtocolTest, ExpressScanIsRequestedWithWorkingModeZeroAndAnsweredWith84ByteCapsules) {
  // A5 82, five payload bytes (mode 0, four reserved), the XOR of all before: A5 ^ 82 ^ 05 = 22.
  EXPECT_EQ(EncodeExpressScanRequest(), (Bytes{0xA5, 0x82, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x22}));
  const std::array<std::uint8_t, kDescriptorBytes> answer = {0xA5, 0x5A, 0x54, 0x00, 0x00, 0x40, 0x82};
  const std::optional<Descriptor> d = DecodeDescriptor(answer);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->length, kCapsuleBytes);
  EXPECT_TRUE(d->repeated);
  EXPECT_EQ(d->type, static_cast<std::uint8_t>(DataType::kCapsule));
}

TEST(RplidarProtocolTest, ACapsuleIsSyncNibblesOverItsChecksumTheStartAngleAndSixteenCabins) {
  // Built by hand from the document's figure: start angle 90 degrees (0x1680) with S set; cabin 0's first sample
  // 1000 mm with a correction of +1.5 degrees (12 eighths: 0b001100), its second 2000 mm with -0.5 (-4: 0b111100);
  // every other sample none, correction 0.
  std::array<std::uint8_t, kCapsuleBytes> bytes{};
  bytes[2] = 0x80;
  bytes[3] = 0x16 | 0x80;
  const std::uint16_t first = 1000 << 2 | 0b00;   // correction's bits 5:4 = 00
  const std::uint16_t second = 2000 << 2 | 0b11;  // 11
  bytes[4] = first & 0xFF;
  bytes[5] = first >> 8;
  bytes[6] = second & 0xFF;
  bytes[7] = second >> 8;
  bytes[8] = 0b1100 | 0b1100 << 4;  // the first's bits 3:0 low, the second's high
  std::uint8_t checksum = 0;
  for (std::size_t i = 2; i < kCapsuleBytes; ++i) checksum ^= bytes[i];
  bytes[0] = 0xA0 | (checksum & 0x0F);
  bytes[1] = 0x50 | checksum >> 4;
  const std::optional<Capsule> capsule = DecodeCapsule(bytes);
  ASSERT_TRUE(capsule);
  EXPECT_TRUE(capsule->start);
  EXPECT_DOUBLE_EQ(capsule->start_angle_deg, 90.0);
  EXPECT_DOUBLE_EQ(capsule->distance_m[0], 1.0);
  EXPECT_DOUBLE_EQ(capsule->correction_deg[0], 1.5);
  EXPECT_DOUBLE_EQ(capsule->distance_m[1], 2.0);
  EXPECT_DOUBLE_EQ(capsule->correction_deg[1], -0.5);
  EXPECT_DOUBLE_EQ(capsule->distance_m[2], 0.0);
  EXPECT_EQ(EncodeCapsule(*capsule), bytes);
  // A wrong checksum, wrong sync nibbles, an angle of 360 degrees or more: not a capsule.
  auto broken = bytes;
  broken[10] ^= 0x01;
  EXPECT_FALSE(DecodeCapsule(broken));
  broken = bytes;
  broken[0] = 0xB0 | (checksum & 0x0F);
  EXPECT_FALSE(DecodeCapsule(broken));
  Capsule wide = *capsule;
  auto past = EncodeCapsule(wide);
  past[2] = 0x00;
  past[3] = 0x5A;  // 0x5A00 / 64 = 360 degrees
  std::uint8_t c = 0;
  for (std::size_t i = 2; i < kCapsuleBytes; ++i) c ^= past[i];
  past[0] = 0xA0 | (c & 0x0F);
  past[1] = 0x50 | c >> 4;
  EXPECT_FALSE(DecodeCapsule(past));
}

TEST(RplidarProtocolTest, ACapsulesSamplesLieBetweenItsStartAngleAndTheNextLessTheirCorrections) {
  Capsule capsule;
  capsule.start_angle_deg = 350.0;
  capsule.distance_m.fill(1.0);
  capsule.correction_deg[0] = 0.5;
  capsule.correction_deg[16] = -0.25;
  std::vector<SweepPoint> points;
  CapsuleSamples(capsule, 6.0, points);  // the next starts at 6 degrees: 16 degrees on, through forward
  ASSERT_EQ(points.size(), kCapsuleSamples);
  EXPECT_DOUBLE_EQ(points[0].angle_deg, 349.5);
  EXPECT_DOUBLE_EQ(points[1].angle_deg, 350.5);
  EXPECT_DOUBLE_EQ(points[16].angle_deg, 358.25);
  EXPECT_DOUBLE_EQ(points[20].angle_deg, 0.0);
  EXPECT_DOUBLE_EQ(points[31].angle_deg, 5.5);
  // The revolution starts at the sample whose place passes forward, whatever its correction.
  for (std::size_t k = 0; k < points.size(); ++k) EXPECT_EQ(points[k].start, k == 20) << k;
  EXPECT_GT(points[0].quality, 0);
}

// Capsules of 32 samples over `count` samples a revolution, from sample `first` on, each sample at `range(angle)`.
Bytes Capsules(int first, int capsules, int count, double (*range)(double), bool start) {
  Bytes out;
  for (int i = 0; i < capsules; ++i) {
    Capsule capsule;
    capsule.start = start && i == 0;
    capsule.start_angle_deg = std::fmod(360.0 * (first + i * 32) / count, 360.0);
    for (std::size_t k = 0; k < kCapsuleSamples; ++k) {
      capsule.correction_deg[k] = (static_cast<int>(k) % 3 - 1) * 0.125;
      const double angle = capsule.start_angle_deg + 360.0 * static_cast<double>(k) / count - capsule.correction_deg[k];
      capsule.distance_m[k] = range(std::fmod(angle + 360.0, 360.0));
    }
    const auto bytes = EncodeCapsule(capsule);
    out.insert(out.end(), bytes.begin(), bytes.end());
  }
  return out;
}

TEST(RplidarProtocolTest, TheCapsuleStreamDropsOnlyTheCapsulesANoiseBurstOrABadChecksumTouches) {
  // Twelve capsules; noise before the first, a lost byte in the sixth. Each capsule's samples come with the next.
  const Bytes clean = Capsules(0, 12, 384, RangeOf, true);
  Bytes bytes = {0x00, 0xA5, 0x5A, 0x13};
  bytes.insert(bytes.end(), clean.begin(), clean.end());
  bytes.erase(bytes.begin() + 4 + 5 * kCapsuleBytes + 30);
  CapsuleStream stream;
  std::vector<SweepPoint> points;
  for (std::size_t at = 0, piece = 1; at < bytes.size(); at += piece, piece = piece % 97 + 1) {
    stream.Push(std::span<const std::uint8_t>(bytes).subspan(at, std::min(piece, bytes.size() - at)), points);
  }
  EXPECT_EQ(stream.capsules(), 11u);
  EXPECT_GT(stream.skipped_bytes(), 0u);
  // Capsules 0-3 (4 waits for 5, which is broken, and is dropped), 6-10 (11 waits): nine of them.
  EXPECT_EQ(points.size(), 9 * kCapsuleSamples);
  for (const SweepPoint& p : points) EXPECT_NEAR(p.distance_m, RangeOf(p.angle_deg), 1e-3) << p.angle_deg;
}

TEST(RplidarProtocolTest, ExpressRevolutionsBecomeScansWhereTheAngleFallsBackPastForward) {
  SweepOptions options;
  options.bins = 360;
  SweepAssembler sweeps(options);
  CapsuleStream stream;
  std::vector<SweepPoint> points;
  // 720 samples a revolution (an A1 at 5.5 Hz in express mode): 22.5 capsules, so revolutions begin mid-capsule.
  stream.Push(Capsules(0, 70, 720, RangeOf, true), points);
  std::vector<LaserScan> scans;
  for (const SweepPoint& p : points) {
    if (auto scan = sweeps.Add(p, 1)) scans.push_back(std::move(*scan));
  }
  // 69 capsules' samples (the 70th waits for the next): revolutions begin at samples 0, 720, 1440 and 2160.
  ASSERT_EQ(scans.size(), 3u);
  for (const LaserScan& scan : scans) {
    const auto at = [&](double deg) {
      const double a = deg * std::numbers::pi / 180.0;
      return scan
          .ranges[static_cast<std::size_t>(std::lround((a - scan.angle_min_rad) / scan.angle_increment_rad)) % 360];
    };
    EXPECT_NEAR(at(-90.0), RangeOf(90.0), 2e-3);
    EXPECT_NEAR(at(90.0), RangeOf(270.0), 2e-3);
  }
}

}  // namespace
}  // namespace corridor::drivers::rplidar
