#include "drivers/dynamixel/dynamixel_protocol.h"

#include <gtest/gtest.h>

#include <string_view>

namespace corridor::drivers::dynamixel {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(DynamixelProtocolTest, TheCrcIsCrc16WithPolynomial8005) {
  const std::string_view check = "123456789";
  EXPECT_EQ(Crc16(std::span(reinterpret_cast<const std::uint8_t*>(check.data()), check.size())), 0xFEE8);
}

// The e-Manual's own examples of Protocol 2.0 packets, byte for byte.
TEST(DynamixelProtocolTest, InstructionsAreFramedAsTheManualsExamples) {
  EXPECT_EQ(EncodePing(1), (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E}));
  // Read 4 bytes at 132 (an X-series servo's Present Position).
  EXPECT_EQ(EncodeRead(1, 132, 4),
            (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x02, 0x84, 0x00, 0x04, 0x00, 0x1D, 0x15}));
  // Write 512 into the 4 bytes at 116 (Goal Position).
  const Bytes goal{0x00, 0x02, 0x00, 0x00};
  EXPECT_EQ(EncodeWrite(1, 116, goal),
            (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x03, 0x74, 0x00, 0x00, 0x02, 0x00, 0x00, 0xCA, 0x89}));
  EXPECT_EQ(EncodeReboot(1), (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x08, 0x2F, 0x4E}));
}

TEST(DynamixelProtocolTest, AHeaderInsideAPacketIsStuffedAndUnstuffed) {
  const Bytes data{0xFF, 0xFF, 0xFD, 0x07};
  const Bytes packet = EncodeWrite(200, 150, data);
  // Instruction, address (2), the data with one FD more, CRC (2).
  EXPECT_EQ(packet[5] | packet[6] << 8, 1 + 2 + 5 + 2);
  EXPECT_EQ(Bytes(packet.begin() + 10, packet.begin() + 15), (Bytes{0xFF, 0xFF, 0xFD, 0xFD, 0x07}));
  // A status packet carrying the same bytes is read back without the stuffed FD.
  Bytes status{0xFF, 0xFF, 0xFD, 0x00, 200, 0x09, 0x00, 0x55, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0x07};
  const std::uint16_t crc = Crc16(status);
  status.push_back(crc & 0xFF);
  status.push_back(crc >> 8);
  StatusParser parser;
  std::vector<StatusPacket> out;
  parser.Push(status, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, 200);
  EXPECT_EQ(out[0].parameters, data);
}

TEST(DynamixelProtocolTest, StatusPacketsAreReadThroughNoiseSplitReadsAndBadCrcs) {
  // The manual's answer to the read above: no error, Present Position 166.
  const Bytes answer{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00, 0x8C, 0xC0};
  Bytes corrupt = answer;
  corrupt[9] ^= 0x01;
  Bytes stream{0x00, 0xFF, 0xFD, 0xFF, 0xFF};  // noise, with half a header in it
  stream.insert(stream.end(), corrupt.begin(), corrupt.end());
  stream.insert(stream.end(), answer.begin(), answer.end());
  StatusParser parser;
  std::vector<StatusPacket> out;
  for (std::size_t at = 0; at < stream.size(); at += 4) {
    parser.Push(std::span(stream).subspan(at, std::min<std::size_t>(4, stream.size() - at)), out);
  }
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, 1);
  EXPECT_EQ(out[0].error, 0);
  EXPECT_EQ(ReadInt32(out[0].parameters, 0), 166);
  EXPECT_GE(parser.dropped(), 1u);
  // An instruction packet (an echo on a half-duplex line) is not a status.
  out.clear();
  parser.Push(EncodePing(1), out);
  EXPECT_TRUE(out.empty());
}

TEST(DynamixelProtocolTest, ControlTableValuesAreLittleEndian) {
  Bytes bytes;
  AppendInt32(bytes, -2);
  AppendInt32(bytes, 0x12345678);
  EXPECT_EQ(bytes, (Bytes{0xFE, 0xFF, 0xFF, 0xFF, 0x78, 0x56, 0x34, 0x12}));
  EXPECT_EQ(ReadInt32(bytes, 0), -2);
  EXPECT_EQ(ReadInt32(bytes, 4), 0x12345678);
}

}  // namespace
}  // namespace corridor::drivers::dynamixel
