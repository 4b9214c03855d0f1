// The Create 2 Open Interface's commands and sensor stream byte for byte as iRobot's "Create 2 Open Interface (OI)
// Specification" gives them, and the stream's faults on a serial line: noise, a bad checksum, frames cut anywhere.
#include "drivers/create2/open_interface.h"

#include <gtest/gtest.h>

#include <numbers>
#include <numeric>

namespace corridor::drivers::create2 {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(OpenInterfaceTest, CommandsAreTheirOpcodesAndBigEndianArguments) {
  EXPECT_EQ(EncodeStart(), (Bytes{128}));
  EXPECT_EQ(EncodeSafe(), (Bytes{131}));
  EXPECT_EQ(EncodeStop(), (Bytes{173}));
  // Right wheel first: +500 mm/s is 0x01F4, -200 is 0xFF38; beyond +-500 is clamped.
  EXPECT_EQ(EncodeDriveDirect(-200, 500), (Bytes{145, 0x01, 0xF4, 0xFF, 0x38}));
  EXPECT_EQ(EncodeDriveDirect(-900, 700), (Bytes{145, 0x01, 0xF4, 0xFE, 0x0C}));
  const std::vector<Packet> packets = {Packet::kBumpsAndWheelDrops, Packet::kLeftEncoderCounts};
  EXPECT_EQ(EncodeStream(packets), (Bytes{148, 2, 7, 43}));
  EXPECT_EQ(EncodePauseStream(false), (Bytes{150, 0}));
}

TEST(OpenInterfaceTest, TheSpecificationsStreamExampleParses) {
  // "19 5 29 2 25 13 0 163": packet 29 (2 bytes), packet 13 (1 byte), and a checksum that makes the sum 0 mod 256.
  StreamParser parser;
  std::vector<SensorFrame> frames;
  parser.Push(Bytes{19, 5, 29, 2, 25, 13, 0, 163}, frames);
  EXPECT_EQ(frames.size(), 1u);
  EXPECT_EQ(parser.dropped(), 0u);
}

// A frame of the driver's packets with the given sensor values and its checksum.
Bytes Frame(std::uint8_t bumps, std::uint16_t left, std::uint16_t right, bool bad_checksum = false) {
  Bytes body = {7,    bumps, 9,    0,    10, 0,    11,   0,  12,   1,    21, 2,    22, 0x39,
                0xD0, 23,    0xFB, 0x50, 25, 0x07, 0xD0, 26, 0x0A, 0x88, 34, 0x02, 35, 2};
  for (const auto& [id, counts] : {std::pair<std::uint8_t, std::uint16_t>{43, left}, {44, right}}) {
    body.push_back(id);
    body.push_back(static_cast<std::uint8_t>(counts >> 8));
    body.push_back(static_cast<std::uint8_t>(counts & 0xFF));
  }
  Bytes frame = body;
  frame.insert(frame.begin(), {19, static_cast<std::uint8_t>(body.size())});
  const unsigned sum = std::accumulate(frame.begin(), frame.end(), 0u);
  frame.push_back(static_cast<std::uint8_t>((256 - sum % 256) % 256 + (bad_checksum ? 1 : 0)));
  return frame;
}

TEST(OpenInterfaceTest, AFrameOfTheDriversPacketsDecodesToTheRobotsState) {
  StreamParser parser;
  std::vector<SensorFrame> frames;
  parser.Push(Frame(0x0B, 65530, 12), frames);  // both bumps, the left wheel dropped
  ASSERT_EQ(frames.size(), 1u);
  const SensorFrame& f = frames[0];
  EXPECT_TRUE(f.bump_left && f.bump_right);
  EXPECT_TRUE(f.wheel_drop_left);
  EXPECT_FALSE(f.wheel_drop_right);
  EXPECT_TRUE(f.cliff);  // the right cliff sensor
  EXPECT_EQ(f.charging_state, 2);
  EXPECT_DOUBLE_EQ(f.voltage_v, 14.8);
  EXPECT_DOUBLE_EQ(f.current_a, -1.2);
  EXPECT_DOUBLE_EQ(f.charge_ah, 2.0);
  EXPECT_DOUBLE_EQ(f.capacity_ah, 2.696);
  EXPECT_TRUE(f.on_home_base);
  EXPECT_EQ(f.oi_mode, 2);
  EXPECT_TRUE(f.has_encoders);
  EXPECT_EQ(f.left_counts, 65530);
  EXPECT_EQ(f.right_counts, 12);
  EXPECT_EQ(StreamedPackets().size(), 14u);
}

TEST(OpenInterfaceTest, NoiseABadChecksumAndFramesCutAnywhereLoseOnlyTheBadFrame) {
  Bytes bytes = {0x13, 0x00, 0xFF, 19, 200, 42};  // noise, two bytes of it the header's value
  for (int i = 0; i < 5; ++i) {
    const Bytes frame = Frame(0, static_cast<std::uint16_t>(100 * i), static_cast<std::uint16_t>(100 * i), i == 2);
    bytes.insert(bytes.end(), frame.begin(), frame.end());
  }
  StreamParser parser;
  std::vector<SensorFrame> frames;
  for (std::size_t at = 0, piece = 1; at < bytes.size(); at += piece, piece = piece % 9 + 1) {
    parser.Push(std::span<const std::uint8_t>(bytes).subspan(at, std::min(piece, bytes.size() - at)), frames);
  }
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[1].left_counts, 100);
  EXPECT_EQ(frames[2].left_counts, 300);  // the third frame's checksum was bad
  EXPECT_GE(parser.dropped(), 1u);
}

}  // namespace
}  // namespace corridor::drivers::create2
