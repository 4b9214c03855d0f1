// The RPLIDAR protocol's frames byte for byte as Slamtec's "RPLIDAR Interface Protocol and Application Notes" gives
// them, and the byte stream's faults a serial port shows: noise before the first frame, a byte lost, a bad check bit.
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
    return scan->ranges[static_cast<std::size_t>(std::lround((a - scan->angle_min_rad) / scan->angle_increment_rad)) % 360];
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
  sweeps.Add(Node{false, 0, 45.0, 2.0}, 1);    // the device saw nothing
  sweeps.Add(Node{false, 40, 90.0, 0.05}, 1);  // inside the housing
  sweeps.Add(Node{false, 40, 135.0, 30.0}, 1); // past the range
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

}  // namespace
}  // namespace corridor::drivers::rplidar
