#include "drivers/sim/diff_drive_sim.h"

#include <gtest/gtest.h>

#include <numbers>

namespace corridor::drivers::sim {
namespace {

// A 10 x 10 m free room with a 5 cm border of walls, and a wall across x = 6.
nav::OccupancyGrid Room() {
  nav::OccupancyGrid g(200, 200, 0.05, {}, nav::kFreeCell);
  for (int i = 0; i < 200; ++i) {
    g.at({i, 0}) = g.at({i, 199}) = g.at({0, i}) = g.at({199, i}) = nav::kOccupiedCell;
    g.at({120, i}) = nav::kOccupiedCell;
  }
  return g;
}

SimBaseOptions NoiselessBase() {
  SimBaseOptions o;
  o.odom_linear_noise = 0.0;
  o.odom_angular_noise = 0.0;
  return o;
}

void Drive(DiffDriveSim& base, const nav::Twist2& command, double seconds, double& now_s, std::mt19937& rng,
           bool keep_commanding = true) {
  constexpr double kDt = 0.01;
  for (int i = 0; i < static_cast<int>(seconds / kDt); ++i) {
    now_s += kDt;
    if (keep_commanding) base.Command(command, now_s);
    base.Step(kDt, now_s, rng);
  }
}

TEST(DriveArcTest, FullCircleReturnsToStart) {
  nav::Pose2 p{1.0, 2.0, 0.3};
  for (int i = 0; i < 1000; ++i) p = nav::DriveArc(p, {0.5, 2.0 * std::numbers::pi / 10.0}, 0.01);
  EXPECT_NEAR(p.x_m, 1.0, 1e-9);
  EXPECT_NEAR(p.y_m, 2.0, 1e-9);
  EXPECT_NEAR(p.yaw_rad, 0.3, 1e-9);
}

TEST(DiffDriveSimTest, DrivesStraightWithinAccelerationAndSpeedLimits) {
  const nav::OccupancyGrid room = Room();
  SimBaseOptions o = NoiselessBase();
  DiffDriveSim base(room, o, {2.0, 5.0, 0.0});
  std::mt19937 rng(1);
  double now = 0.0;
  Drive(base, {5.0, 0.0}, 2.0, now, rng);  // asks for more than the 0.6 m/s limit
  EXPECT_NEAR(base.velocity().linear_mps, 0.6, 1e-9);
  // 0.6 s ramp at 1 m/s^2 covers 0.18 m, then 1.4 s at 0.6 m/s: 1.02 m.
  EXPECT_NEAR(base.pose().x_m, 2.0 + 0.18 + 0.84, 0.01);
  EXPECT_NEAR(base.pose().y_m, 5.0, 1e-9);
  EXPECT_NEAR(base.odom_pose().x_m, base.pose().x_m - 2.0, 1e-9);
}

TEST(DiffDriveSimTest, StopsByItselfWhenCommandsLapse) {
  const nav::OccupancyGrid room = Room();
  DiffDriveSim base(room, NoiselessBase(), {2.0, 5.0, 0.0});
  std::mt19937 rng(1);
  double now = 0.0;
  Drive(base, {0.4, 0.0}, 1.0, now, rng);
  Drive(base, {}, 0.45, now, rng, /*keep_commanding=*/false);
  EXPECT_GT(base.velocity().linear_mps, 0.3);  // still within the 0.5 s timeout
  Drive(base, {}, 1.0, now, rng, /*keep_commanding=*/false);
  EXPECT_DOUBLE_EQ(base.velocity().linear_mps, 0.0);
}

TEST(DiffDriveSimTest, NeverPassesThroughAWallAndPressesItsBumper) {
  const nav::OccupancyGrid room = Room();
  SimBaseOptions o = NoiselessBase();
  DiffDriveSim base(room, o, {5.0, 5.0, 0.0});
  std::mt19937 rng(1);
  double now = 0.0;
  bool bumped = false;
  for (int i = 0; i < 500; ++i) {
    Drive(base, {0.6, 0.0}, 0.01, now, rng);
    bumped |= base.bumper_pressed();
    // The wall's near face is at x = 6.0; the footprint's edge never crosses it.
    ASSERT_LE(base.pose().x_m + o.limits.footprint_radius_m, 6.0 + 1e-9);
  }
  EXPECT_TRUE(bumped);
  EXPECT_TRUE(base.bumper_pressed());
  EXPECT_GT(base.pose().x_m + o.limits.footprint_radius_m, 6.0 - 0.05);  // it did reach the wall
  // It can still turn and back away.
  Drive(base, {-0.3, 0.0}, 1.0, now, rng);
  EXPECT_FALSE(base.bumper_pressed());
  EXPECT_LT(base.pose().x_m, 5.6);
}

TEST(DiffDriveSimTest, CollidesAgreesWithBruteForceOverRandomPoses) {
  const nav::OccupancyGrid room = Room();
  const SimBaseOptions o = NoiselessBase();
  const DiffDriveSim base(room, o, {5.0, 5.0, 0.0});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.3, 9.7);
  for (int i = 0; i < 2000; ++i) {
    const nav::Pose2 p{u(rng), u(rng), 0.0};
    // Brute force: the nearest occupied cell's nearest point, over the whole grid.
    double nearest = 1e9;
    for (int y = 0; y < room.height(); ++y) {
      for (int x = 0; x < room.width(); ++x) {
        if (room.at({x, y}) != nav::kOccupiedCell) continue;
        const double nx = std::clamp(p.x_m, x * 0.05, (x + 1) * 0.05);
        const double ny = std::clamp(p.y_m, y * 0.05, (y + 1) * 0.05);
        nearest = std::min(nearest, std::hypot(p.x_m - nx, p.y_m - ny));
      }
    }
    if (std::abs(nearest - o.limits.footprint_radius_m) < 1e-6) continue;  // on the boundary
    EXPECT_EQ(base.Collides(p), nearest < o.limits.footprint_radius_m) << p.x_m << ", " << p.y_m;
  }
}

}  // namespace
}  // namespace corridor::drivers::sim
