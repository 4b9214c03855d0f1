#include "drivers/kobuki/kobuki_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace corridor::drivers::kobuki {
namespace {

TEST(KobukiProtocolTest, BaseControlIsFramedByteForByte) {
  // 100 mm/s straight: headers, length 6, Base Control (id 1, 4 bytes: speed and radius, little-endian), and the XOR
  // of the length and the payload.
  EXPECT_EQ(EncodeBaseControl({100, 0}),
            (std::vector<std::uint8_t>{0xAA, 0x55, 0x06, 0x01, 0x04, 0x64, 0x00, 0x00, 0x00, 0x67}));
  // -300 mm/s on a -500 mm arc: 0xFED4, 0xFE0C.
  EXPECT_EQ(EncodeBaseControl({-300, -500}),
            (std::vector<std::uint8_t>{0xAA, 0x55, 0x06, 0x01, 0x04, 0xD4, 0xFE, 0x0C, 0xFE,
                                       0x06 ^ 0x01 ^ 0x04 ^ 0xD4 ^ 0xFE ^ 0x0C ^ 0xFE}));
  EXPECT_THROW(EncodePacket(std::vector<std::uint8_t>(256, 0)), std::invalid_argument);
}

// The wheels' speeds a Base Control means (the specification's arc: the outer wheel at the speed).
std::pair<double, double> Wheels(const BaseControl& c, double track_m) {
  const double speed = c.speed_mmps / 1000.0;
  if (c.radius_mm == 0) return {speed, speed};
  if (c.radius_mm == 1) return {-speed, speed};
  const double r = std::abs(c.radius_mm) / 1000.0;
  const double inner = speed * (r - track_m / 2.0) / (r + track_m / 2.0);
  return c.radius_mm > 0 ? std::make_pair(inner, speed) : std::make_pair(speed, inner);
}

TEST(KobukiProtocolTest, ATwistBecomesTheSpeedAndRadiusThatDriveIt) {
  const double track = 0.230;
  EXPECT_EQ(ToBaseControl({0.25, 0.0}, track).radius_mm, 0);
  EXPECT_EQ(ToBaseControl({0.25, 0.0}, track).speed_mmps, 250);
  const BaseControl spin = ToBaseControl({0.0, 1.0}, track);
  EXPECT_EQ(spin.radius_mm, 1);
  EXPECT_EQ(spin.speed_mmps, 115);
  for (const nav::Twist2& t : {nav::Twist2{0.2, 0.5}, nav::Twist2{0.2, -0.5}, nav::Twist2{-0.2, 0.5},
                               nav::Twist2{-0.3, -1.2}, nav::Twist2{0.5, 0.05}}) {
    const auto [left, right] = Wheels(ToBaseControl(t, track), track);
    EXPECT_NEAR(0.5 * (left + right), t.linear_mps, 0.003) << t.linear_mps << " " << t.angular_rps;
    EXPECT_NEAR((right - left) / track, t.angular_rps, 0.02) << t.linear_mps << " " << t.angular_rps;
  }
  // An arc too wide for its radius to fit in 16 bits drives straight.
  EXPECT_EQ(ToBaseControl({0.5, 0.001}, track).radius_mm, 0);
}

// A feedback packet as the Kobuki sends it: Basic Sensor Data, Inertial Sensor, and Current (which the driver skips).
std::vector<std::uint8_t> Feedback(std::uint16_t left, std::uint16_t right) {
  std::vector<std::uint8_t> payload{1,
                                    15,
                                    0x10,
                                    0x27,  // time stamp 10000 ms
                                    0x04,  // bumper: left
                                    0x00,  // wheel drop: none
                                    0x02,  // cliff: centre
                                    static_cast<std::uint8_t>(left & 0xFF),
                                    static_cast<std::uint8_t>(left >> 8),
                                    static_cast<std::uint8_t>(right & 0xFF),
                                    static_cast<std::uint8_t>(right >> 8),
                                    0,
                                    0,
                                    0,                               // PWM left, right; buttons
                                    6,                               // charger: on the dock, charging
                                    158,                             // battery: 15.8 V
                                    0};                              // over-current: none
  payload.insert(payload.end(), {4, 7, 0x28, 0x23, 0, 0, 0, 0, 0});  // heading 90.00 degrees
  payload.insert(payload.end(), {6, 2, 12, 12});
  return EncodePacket(payload);
}

TEST(KobukiProtocolTest, FeedbackIsDecodedInPiecesOfAnySize) {
  std::vector<std::uint8_t> bytes = Feedback(65530, 4);
  const std::vector<std::uint8_t> second = Feedback(100, 200);
  bytes.insert(bytes.end(), second.begin(), second.end());
  PacketParser parser;
  std::vector<FeedbackPacket> packets;
  for (std::size_t at = 0, piece = 1; at < bytes.size(); at += piece, piece = piece % 7 + 1) {
    parser.Push(std::span<const std::uint8_t>(bytes).subspan(at, std::min(piece, bytes.size() - at)), packets);
  }
  ASSERT_EQ(packets.size(), 2u);
  ASSERT_TRUE(packets[0].sensors);
  const SensorData& s = *packets[0].sensors;
  EXPECT_EQ(s.timestamp_ms, 10000);
  EXPECT_TRUE(s.bump_left);
  EXPECT_FALSE(s.bump_right);
  EXPECT_TRUE(s.cliff);
  EXPECT_FALSE(s.wheel_drop_left || s.wheel_drop_right);
  EXPECT_EQ(s.left_counts, 65530);
  EXPECT_EQ(s.right_counts, 4);
  EXPECT_NEAR(s.battery_v, 15.8, 1e-9);
  EXPECT_TRUE(Charging(s.charger));
  EXPECT_TRUE(OnDock(s.charger));
  EXPECT_FALSE(OnDock(22));  // charging on the adapter
  EXPECT_NEAR(*packets[0].heading_rad, std::numbers::pi / 2.0, 1e-9);
  EXPECT_EQ(packets[1].sensors->right_counts, 200);
  EXPECT_EQ(parser.dropped(), 0u);
}

TEST(KobukiProtocolTest, NoiseAndABadChecksumCostOnlyWhatTheyTouch) {
  std::vector<std::uint8_t> bytes{0x13, 0xAA, 0x00, 0x55, 0xAA};  // noise, with header bytes in it
  std::vector<std::uint8_t> bad = Feedback(1, 1);
  bad.back() ^= 0xFF;
  bytes.insert(bytes.end(), bad.begin(), bad.end());
  const std::vector<std::uint8_t> good = Feedback(2, 2);
  bytes.insert(bytes.end(), good.begin(), good.end());
  // A packet whose sub-payloads overrun its length is no packet either.
  std::vector<std::uint8_t> overrun = EncodePacket(std::vector<std::uint8_t>{1, 15, 0, 0});
  bytes.insert(bytes.end(), overrun.begin(), overrun.end());
  bytes.insert(bytes.end(), good.begin(), good.end());
  PacketParser parser;
  std::vector<FeedbackPacket> packets;
  parser.Push(bytes, packets);
  ASSERT_EQ(packets.size(), 2u);
  EXPECT_EQ(packets[0].sensors->left_counts, 2);
  EXPECT_EQ(packets[1].sensors->left_counts, 2);
  EXPECT_GE(parser.dropped(), 2u);
  EXPECT_GE(parser.skipped(), 4u);
}

}  // namespace
}  // namespace corridor::drivers::kobuki
