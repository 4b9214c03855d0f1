#include "nav/geometry/pose2.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace corridor::nav {
namespace {

TEST(WrapAngleTest, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(std::numbers::pi), std::numbers::pi);
  EXPECT_DOUBLE_EQ(WrapAngle(-std::numbers::pi), std::numbers::pi);
  EXPECT_NEAR(WrapAngle(3.0 * std::numbers::pi / 2.0), -std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(WrapAngle(7.0), 7.0 - 2.0 * std::numbers::pi, 1e-12);
}

TEST(Pose2Test, ComposeWithInverseIsIdentityOverRandomPoses) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> pos(-50.0, 50.0);
  std::uniform_real_distribution<double> ang(-10.0, 10.0);
  for (int i = 0; i < 1000; ++i) {
    const Pose2 a{pos(rng), pos(rng), ang(rng)};
    const Pose2 identity = a * a.Inverse();
    EXPECT_NEAR(identity.x_m, 0.0, 1e-9);
    EXPECT_NEAR(identity.y_m, 0.0, 1e-9);
    EXPECT_NEAR(identity.yaw_rad, 0.0, 1e-9);
  }
}

TEST(Pose2Test, TransformAgreesWithIsometry3) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int i = 0; i < 200; ++i) {
    const Pose2 a{u(rng), u(rng), u(rng)};
    const Pose2 b{u(rng), u(rng), u(rng)};
    const Eigen::Vector2d p(u(rng), u(rng));
    const Eigen::Vector2d expected = (a.ToIsometry3() * b.ToIsometry3() * Eigen::Vector3d(p.x(), p.y(), 0)).head<2>();
    EXPECT_TRUE((a * b).Transform(p).isApprox(expected, 1e-9));
  }
}

}  // namespace
}  // namespace corridor::nav
