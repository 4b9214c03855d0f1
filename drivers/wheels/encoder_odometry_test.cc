#include "drivers/wheels/encoder_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace corridor::drivers {
namespace {

const WheelGeometry kWheels{0.072, 0.235, 508.8};  // a Create 2's

TEST(EncoderOdometryTest, CountsWrapEitherWayAndBecomeMetres) {
  EXPECT_EQ(CountsDelta(100, 150), 50);
  EXPECT_EQ(CountsDelta(65530, 4), 10);
  EXPECT_EQ(CountsDelta(4, 65530), -10);
  EXPECT_NEAR(CountsToMetres(509, kWheels), std::numbers::pi * 0.072 * 509 / 508.8, 1e-12);
  EXPECT_NEAR(CountsToMetres(-509, kWheels), -CountsToMetres(509, kWheels), 1e-12);
}

TEST(EncoderOdometryTest, StraightAcrossTheWrapAndATurnOnTheSpot) {
  EncoderOdometry odometry(kWheels);
  const double per_metre = 508.8 / (std::numbers::pi * 0.072);
  // 1 m straight in 1 s, in 50 reports, starting 100 counts short of the wrap.
  std::uint16_t left = 65436;
  std::uint16_t right = 65436;
  odometry.Update(0, left, right);
  for (int i = 1; i <= 50; ++i) {
    const auto counts = static_cast<std::uint16_t>(65436 + std::lround(per_metre * i / 50.0));
    left = right = counts;
    odometry.Update(FromSeconds(i / 50.0), left, right);
  }
  EXPECT_NEAR(odometry.pose().x_m, 1.0, 0.002);
  EXPECT_NEAR(odometry.pose().y_m, 0.0, 1e-9);
  EXPECT_NEAR(odometry.velocity().linear_mps, 1.0, 0.02);
  // A quarter turn counter-clockwise on the spot: each wheel rolls a quarter of the track's circle.
  const int quarter = static_cast<int>(std::lround(per_metre * std::numbers::pi * 0.235 / 4.0));
  odometry.Update(FromSeconds(1.5), static_cast<std::uint16_t>(left - quarter),
                  static_cast<std::uint16_t>(right + quarter));
  EXPECT_NEAR(odometry.pose().yaw_rad, std::numbers::pi / 2.0, 0.01);
  EXPECT_NEAR(odometry.pose().x_m, 1.0, 0.002);
}

TEST(EncoderOdometryTest, ARestartedDeviceCountsAnewFromWhereTheRobotIs) {
  EncoderOdometry odometry(kWheels);
  odometry.Update(0, 0, 0);
  odometry.Update(FromSeconds(0.1), 1000, 1000);
  const double x = odometry.pose().x_m;
  odometry.Restart();
  odometry.Update(FromSeconds(0.2), 30000, 30000);  // whatever the device counts from now
  EXPECT_DOUBLE_EQ(odometry.pose().x_m, x);
  EXPECT_DOUBLE_EQ(odometry.velocity().linear_mps, 0.0);
  EXPECT_THROW(EncoderOdometry(WheelGeometry{}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers
