// The TurtleBot 3 lasers' packets byte for byte, as their documents lay them out (lds_protocol.h).
#include "drivers/lds/lds_protocol.h"

#include <gtest/gtest.h>

#include <vector>

namespace corridor::drivers::lds {
namespace {

using Bytes = std::vector<std::uint8_t>;

void Put16(Bytes& out, unsigned value) {
  out.push_back(static_cast<std::uint8_t>(value & 0xFF));
  out.push_back(static_cast<std::uint8_t>(value >> 8));
}

// An LDS-02 packet from start to end (1/100 degree), point i at 1000 + i mm with intensity 100 + i.
Bytes Ld08(unsigned start, unsigned end) {
  Bytes out = {0x54, 0x2C};
  Put16(out, 2160);  // 6 turns a second
  Put16(out, start);
  for (unsigned i = 0; i < 12; ++i) {
    Put16(out, 1000 + i);
    out.push_back(static_cast<std::uint8_t>(100 + i));
  }
  Put16(out, end);
  Put16(out, 29999);
  out.push_back(Crc8(out));
  return out;
}

// An LDS-01 packet: index n, reading i at 500 + 6n + i mm with intensity 300.
Bytes Lfcd(unsigned n) {
  Bytes out = {0xFA, static_cast<std::uint8_t>(0xA0 + n)};
  Put16(out, 3000);
  for (unsigned i = 0; i < 6; ++i) {
    Put16(out, 300);
    Put16(out, 500 + 6 * n + i);
    Put16(out, 0);
  }
  Put16(out, 0);
  return out;
}

TEST(LdsProtocolTest, TheCrcIsLdrobotsTable) {
  // Entries of the CRC table printed in LDROBOT's manual: the CRC of one byte n is its entry n.
  EXPECT_EQ(Crc8(Bytes{0x00}), 0x00);
  EXPECT_EQ(Crc8(Bytes{0x01}), 0x4D);
  EXPECT_EQ(Crc8(Bytes{0x02}), 0x9A);
  EXPECT_EQ(Crc8(Bytes{0x03}), 0xD7);
  EXPECT_EQ(Crc8(Bytes{0x10}), 0xA9);
  EXPECT_EQ(Crc8(Bytes{0x20}), 0x1F);
  EXPECT_EQ(Crc8(Bytes{0x30}), 0xB6);
}

TEST(LdsProtocolTest, AnLds02PacketDecodesAndItsPointsSpanStartToEnd) {
  const Bytes bytes = Ld08(35500, 1100);  // 355.00 to 11.00 degrees: across forward
  ASSERT_EQ(bytes.size(), kLd08PacketBytes);
  const std::optional<Ld08Packet> packet =
      DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes>(bytes.data(), kLd08PacketBytes));
  ASSERT_TRUE(packet);
  EXPECT_DOUBLE_EQ(packet->speed_deg_s, 2160.0);
  EXPECT_DOUBLE_EQ(packet->start_deg, 355.0);
  EXPECT_DOUBLE_EQ(packet->end_deg, 11.0);
  EXPECT_EQ(packet->distance_mm[3], 1003);
  EXPECT_EQ(packet->intensity[11], 111);
  EXPECT_EQ(packet->timestamp_ms, 29999);
  EXPECT_NEAR(Ld08Angle(*packet, 0), 355.0, 1e-9);
  EXPECT_NEAR(Ld08Angle(*packet, 11), 11.0, 1e-9);
  EXPECT_NEAR(Ld08Angle(*packet, 5), 2.2727, 1e-3);  // 355 + 5 * 16 / 11, a turn on
}

TEST(LdsProtocolTest, AnLds02PacketWithABadCrcHeaderOrAngleIsRefused) {
  for (const std::size_t at : {std::size_t{0}, std::size_t{1}, std::size_t{9}, std::size_t{46}}) {
    Bytes bytes = Ld08(0, 1100);
    bytes[at] ^= 0x01;
    EXPECT_FALSE(DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes>(bytes.data(), kLd08PacketBytes))) << at;
  }
  const Bytes beyond = Ld08(36000, 100);  // 360.00 degrees: not an angle the device sends
  EXPECT_FALSE(DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes>(beyond.data(), kLd08PacketBytes)));
}

TEST(LdsProtocolTest, AnLds01PacketDecodesAndAWrongIndexIsRefused) {
  const Bytes bytes = Lfcd(59);
  ASSERT_EQ(bytes.size(), kLfcdPacketBytes);
  const std::optional<LfcdPacket> packet =
      DecodeLfcd(std::span<const std::uint8_t, kLfcdPacketBytes>(bytes.data(), kLfcdPacketBytes));
  ASSERT_TRUE(packet);
  EXPECT_EQ(packet->index, 59);
  EXPECT_EQ(packet->speed, 3000);
  EXPECT_EQ(packet->distance_mm[5], 500 + 6 * 59 + 5);
  EXPECT_EQ(packet->intensity[0], 300);
  Bytes beyond = Lfcd(0);
  beyond[1] = 0xDC;  // one past the last index
  EXPECT_FALSE(DecodeLfcd(std::span<const std::uint8_t, kLfcdPacketBytes>(beyond.data(), kLfcdPacketBytes)));
}

TEST(LdsProtocolTest, TheStreamSkipsNoiseAndBadPacketsAndMarksEachRevolution) {
  PacketStream stream(Model::kLds02);
  Bytes bytes = {0x54, 0x00, 0x13};  // noise that begins like a header
  const auto append = [&](const Bytes& b) { bytes.insert(bytes.end(), b.begin(), b.end()); };
  append(Ld08(33000, 34100));
  append(Ld08(34200, 35300));
  Bytes bad = Ld08(35400, 500);
  bad[20] ^= 0x80;  // its CRC fails: its 12 points are lost
  append(bad);
  append(Ld08(600, 1700));
  std::vector<SweepPoint> points;
  for (const std::uint8_t b : bytes) stream.Push(std::span<const std::uint8_t>(&b, 1), points);  // byte by byte
  ASSERT_EQ(points.size(), 36u);
  EXPECT_EQ(stream.packets(), 3u);
  EXPECT_EQ(stream.skipped_bytes(), 3u + kLd08PacketBytes);
  EXPECT_NEAR(points[0].angle_deg, 330.0, 1e-9);
  EXPECT_NEAR(points[0].distance_m, 1.0, 1e-9);
  EXPECT_EQ(points[0].quality, 100);
  int starts = 0;
  for (std::size_t i = 0; i < points.size(); ++i) starts += points[i].start ? 1 : 0;
  EXPECT_EQ(starts, 1);
  EXPECT_TRUE(points[24].start);  // the first point past forward
  EXPECT_NEAR(points[24].angle_deg, 6.0, 1e-9);
  EXPECT_DOUBLE_EQ(stream.speed_deg_s(), 2160.0);
}

TEST(LdsProtocolTest, AnLds01PacketIsTakenOnlyWhenTheNextFollowsSoALostByteCostsOnePacket) {
  PacketStream stream(Model::kLds01);
  Bytes bytes;
  const auto append = [&](const Bytes& b) { bytes.insert(bytes.end(), b.begin(), b.end()); };
  append(Lfcd(58));
  Bytes cut = Lfcd(59);
  cut.erase(cut.begin() + 10);  // a byte lost: the packet runs one byte into the next
  append(cut);
  append(Lfcd(0));
  append(Lfcd(1));
  append(Lfcd(2));
  std::vector<SweepPoint> points;
  stream.Push(bytes, points);
  // 58 (59 follows), 0 and 1; 2 waits for what follows it.
  ASSERT_EQ(points.size(), 18u);
  EXPECT_NEAR(points[0].angle_deg, 348.0, 1e-9);
  EXPECT_NEAR(points[6].angle_deg, 0.0, 1e-9);
  EXPECT_TRUE(points[6].start);
  EXPECT_NEAR(points[6].distance_m, 0.5, 1e-9);
  EXPECT_EQ(stream.packets(), 3u);
  EXPECT_EQ(stream.skipped_bytes(), kLfcdPacketBytes - 1);
  points.clear();
  stream.Push(Lfcd(3), points);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_NEAR(points[0].angle_deg, 12.0, 1e-9);
}

}  // namespace
}  // namespace corridor::drivers::lds
