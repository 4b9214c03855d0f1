#include "nav/localization/sensor_calibration.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "nav/localization/test_world.h"

namespace corridor::nav {
namespace {

using testworld::Room;
using testworld::ScanAt;

constexpr double kDeg = std::numbers::pi / 180.0;

// The room's hits seen by a laser at world_T_laser, in the laser's frame, within `range_m`.
std::vector<Eigen::Vector2f> LaserHits(const Pose2& world_T_laser, double range_m = 25.0) {
  std::vector<Eigen::Vector2f> hits;
  for (const Eigen::Vector2f& p : ScanAt(Room(), world_T_laser).hits) {
    if (p.norm() <= range_m) hits.push_back(p);
  }
  return hits;
}

TEST(SensorCalibrationTest, TheLasersYawIsFoundAgainstTheCamerasScanFromManyPoses) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-2.5, 3.0);
  std::uniform_real_distribution<double> y(-1.5, 2.5);
  std::uniform_real_distribution<double> yaw(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> error(-12.0 * kDeg, 12.0 * kDeg);
  const Pose2 base_T_camera{0.1, 0.0, 0.0};
  const Pose2 laser_true{-0.05, 0.02, 3.0 * kDeg};  // the laser as it really sits
  int fitted = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const Pose2 world_T_base{x(rng), y(rng), yaw(rng)};
    // The camera's scan: the room within its 60-degree view out to 4 m, base frame, a point every 0.1 degree (a
    // column of a 640-pixel image).
    const SensorView view{base_T_camera, 30.0 * kDeg, 4.0};
    std::vector<Eigen::Vector2d> camera;
    for (const Eigen::Vector2f& p : ScanAt(Room(), world_T_base * base_T_camera, 3600).hits) {
      const Eigen::Vector2d in_base = base_T_camera.Transform(p.cast<double>());
      if (view.Covers(in_base, 0.0)) camera.push_back(in_base);
    }
    const std::vector<Eigen::Vector2f> laser = LaserHits(world_T_base * laser_true);
    const Pose2 configured{laser_true.x_m, laser_true.y_m, laser_true.yaw_rad + error(rng)};
    const LaserYawFit fit = FitLaserYaw(camera, view, laser, configured);
    if (fit.error == CalibrationError::kTooFewPoints) continue;  // facing a wall beyond the camera's 4 m
    ASSERT_EQ(fit.error, CalibrationError::kNone) << fit.detail;
    EXPECT_NEAR(fit.yaw_rad, laser_true.yaw_rad, 0.3 * kDeg) << "trial " << trial;
    EXPECT_GT(fit.score, 0.8);
    ++fitted;
  }
  EXPECT_GE(fitted, 10);
}

TEST(SensorCalibrationTest, ACameraThatSeesNothingIsSaidSo) {
  const SensorView view{Pose2{}, 30.0 * kDeg, 4.0};
  const LaserYawFit fit = FitLaserYaw({}, view, LaserHits(Pose2{}), Pose2{});
  EXPECT_EQ(fit.error, CalibrationError::kTooFewPoints);
  EXPECT_NE(fit.detail.find("camera points"), std::string::npos);
}

// Odometry whose distances are `linear` times and turns `angular` times the truth.
Pose2 Odometry(const Pose2& truth, double linear, double angular) {
  return Pose2{truth.x_m * linear, truth.y_m * linear, truth.yaw_rad * angular};
}

TEST(SensorCalibrationTest, AStraightRunAndATurnMeasureTheWheelsScaleErrors) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> scale(0.94, 1.06);
  for (int trial = 0; trial < 10; ++trial) {
    const double linear = scale(rng);
    const double angular = scale(rng);
    const Pose2 start{-2.0, 0.5, 0.1 * trial};
    // Straight: 1.5 m forward, towards the room's far walls.
    const Pose2 run{1.5, 0.0, 0.0};
    const WheelRunFit straight = FitWheelRun(ScanAt(Room(), start).hits, ScanAt(Room(), start * run).hits, Pose2{},
                                             Odometry(run, linear, angular));
    ASSERT_EQ(straight.error, CalibrationError::kNone) << straight.detail;
    EXPECT_EQ(straight.kind, WheelRunKind::kStraight);
    EXPECT_NEAR(straight.measured, 1.5, 0.01);
    EXPECT_NEAR(straight.factor, 1.0 / linear, 0.007) << "trial " << trial;
    // On the spot: 160 degrees to the left.
    const Pose2 spin{0.0, 0.0, 160.0 * kDeg};
    const WheelRunFit turn = FitWheelRun(ScanAt(Room(), start).hits, ScanAt(Room(), start * spin).hits, Pose2{},
                                         Odometry(spin, linear, angular));
    ASSERT_EQ(turn.error, CalibrationError::kNone) << turn.detail;
    EXPECT_EQ(turn.kind, WheelRunKind::kTurn);
    EXPECT_NEAR(turn.measured, 160.0 * kDeg, 0.3 * kDeg);
    EXPECT_NEAR(turn.factor, angular, 0.004) << "trial " << trial;
  }
}

TEST(SensorCalibrationTest, NeitherARunNorATurnOrACorridorWithoutEndIsRefused) {
  const Pose2 start{-2.0, 0.5, 0.0};
  const auto hits = ScanAt(Room(), start).hits;
  EXPECT_EQ(FitWheelRun(hits, hits, Pose2{}, Pose2{0.2, 0.0, 0.0}).error, CalibrationError::kNotARun);
  EXPECT_EQ(FitWheelRun(hits, hits, Pose2{}, Pose2{1.0, 0.0, 0.5}).error, CalibrationError::kNotARun);
  EXPECT_EQ(FitWheelRun(hits, hits, Pose2{}, Pose2{0.0, 0.0, 0.5}).error, CalibrationError::kNotARun);
  // Two long parallel walls and nothing across: the distance is not pinned.
  const std::vector<testworld::Wall> corridor = {{{-50, -1}, {50, -1}}, {{-50, 1}, {50, 1}}};
  const Pose2 run{1.0, 0.0, 0.0};
  const WheelRunFit fit = FitWheelRun(ScanAt(corridor, Pose2{}).hits, ScanAt(corridor, run).hits, Pose2{}, run);
  EXPECT_EQ(fit.error, CalibrationError::kDegenerate) << fit.detail;
}

}  // namespace
}  // namespace corridor::nav
