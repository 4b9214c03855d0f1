#include "drivers/sim/sensors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace corridor::drivers::sim {
namespace {

SimCameraOptions NoiselessCamera() {
  SimCameraOptions o;
  o.width = 160;
  o.height = 120;
  o.tilt_deg = 0.0;
  o.mount_x_m = 0.0;
  o.mount_height_m = 0.5;
  o.noise_a_m = 0.0;
  o.noise_b_per_m = 0.0;
  o.dropout_fraction = 0.0;
  o.max_range_m = 10.0;
  return o;
}

// A wall facing the robot across x = wall_x, 20 m wide, filling the whole field of view vertically.
TriangleMesh WallAt(float wall_x) {
  TriangleMesh mesh;
  mesh.AddBox({wall_x, -10.0f, -10.0f}, {wall_x + 0.2f, 10.0f, 10.0f}, {1.0f, 0.0f, 0.0f});
  return mesh;
}

RgbdFrame RenderFrom(const TriangleMesh& mesh, const SimCameraOptions& o, const nav::Pose2& base,
                     std::uint32_t seed = 1) {
  const RayCaster caster(mesh);
  const RgbdRenderer renderer(caster, o);
  std::mt19937 rng(seed);
  RgbdFrame frame;
  renderer.Render(base.ToIsometry3() * MakeCameraInfo(o).camera.base_T_camera, rng, frame);
  return frame;
}

TEST(RgbdRendererTest, WallAtKnownDistanceGivesConstantDepth) {
  const SimCameraOptions o = NoiselessCamera();
  const RgbdFrame frame = RenderFrom(WallAt(3.0f), o, {});
  // A plane facing the camera has the same optical-axis depth at every pixel.
  for (int v = 0; v < o.height; v += 7) {
    for (int u = 0; u < o.width; u += 7) EXPECT_NEAR(frame.depth_mm.at<std::uint16_t>(v, u), 3000, 1);
  }
  // The red wall is lit from the camera: red dominates.
  const cv::Vec3b c = frame.color_bgr.at<cv::Vec3b>(o.height / 2, o.width / 2);
  EXPECT_GT(c[2], 200);
  EXPECT_LT(c[1], 10);
}

TEST(RgbdRendererTest, WallAtAnyHeadingKeepsItsPerpendicularDistance) {
  const SimCameraOptions o = NoiselessCamera();
  const TriangleMesh wall = WallAt(4.0f);
  const RayCaster caster(wall);
  const RgbdRenderer renderer(caster, o);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> yaw(-0.5, 0.5);
  for (int trial = 0; trial < 10; ++trial) {
    const double a = yaw(rng);
    RgbdFrame frame;
    renderer.Render(nav::Pose2{1.0, 0.0, a}.ToIsometry3() * MakeCameraInfo(o).camera.base_T_camera, rng, frame);
    // Pixel u's ray is (xn, yn, 1) in the optical frame; its x axis points to the robot's right, which is
    // (sin a, -cos a) in the world. The wall is 3 m ahead in x: 3 = z * (cos a + xn * sin a).
    const nav::PinholeCamera k = MakeCameraInfo(o).camera;
    for (int u = 0; u < o.width; u += 13) {
      const double xn = (u + 0.5 - k.cx) / k.fx;
      const double expected_mm = 3000.0 / (std::cos(a) + xn * std::sin(a));
      EXPECT_NEAR(frame.depth_mm.at<std::uint16_t>(o.height / 2, u), expected_mm, 1.0) << "yaw " << a << " u " << u;
    }
  }
}

TEST(RgbdRendererTest, BoxAppearsWithItsProjectedWidth) {
  SimCameraOptions o = NoiselessCamera();
  TriangleMesh mesh;
  // A 1 m wide box 2 m ahead, its near face at x = 2.
  mesh.AddBox({2.0f, -0.5f, 0.0f}, {3.0f, 0.5f, 1.0f}, {0.0f, 1.0f, 0.0f});
  const RgbdFrame frame = RenderFrom(mesh, o, {});
  const CameraInfo info = MakeCameraInfo(o);
  const int row = static_cast<int>(info.camera.cy) + 2;  // just under the optical axis, below the box top
  int seen = 0;
  for (int u = 0; u < o.width; ++u) {
    const std::uint16_t d = frame.depth_mm.at<std::uint16_t>(row, u);
    if (d > 0) {
      EXPECT_NEAR(d, 2000, 1);
      ++seen;
    }
  }
  const double expected_px = 1.0 / 2.0 * info.camera.fx;
  EXPECT_NEAR(seen, expected_px, 1.5);
}

TEST(RgbdRendererTest, TiltedCameraSeesTheFloorWhereGeometrySaysSo) {
  SimCameraOptions o = NoiselessCamera();
  o.tilt_deg = 20.0;
  TriangleMesh floor;
  floor.AddBox({-20.0f, -20.0f, -0.01f}, {20.0f, 20.0f, 0.0f}, {0.5f, 0.5f, 0.5f});
  const RgbdFrame frame = RenderFrom(floor, o, {});
  const CameraInfo info = MakeCameraInfo(o);
  const double tilt = o.tilt_deg * std::numbers::pi / 180.0;
  for (int v = o.height / 2 + 5; v < o.height; v += 10) {
    // The ray through row v dips below the axis by atan((v + 0.5 - cy) / fy); it meets the floor at range
    // h / sin(dip + tilt), and its depth is that range times cos(dip).
    const double dip = std::atan((v + 0.5 - info.camera.cy) / info.camera.fy);
    const double range = o.mount_height_m / std::sin(dip + tilt);
    const double expected_mm = range * std::cos(dip) * 1000.0;
    EXPECT_NEAR(frame.depth_mm.at<std::uint16_t>(v, o.width / 2), expected_mm, 2.0) << "row " << v;
  }
}

TEST(RgbdRendererTest, NoiseAndHolesFollowTheModel) {
  SimCameraOptions o = NoiselessCamera();
  o.noise_a_m = 0.002;
  o.noise_b_per_m = 0.002;
  o.dropout_fraction = 0.1;
  o.max_range_m = 5.0;
  const RgbdFrame frame = RenderFrom(WallAt(3.0f), o, {}, 11);
  double sum = 0.0;
  double sum_sq = 0.0;
  int valid = 0;
  for (int v = 0; v < o.height; ++v) {
    for (int u = 0; u < o.width; ++u) {
      const double d = frame.depth_mm.at<std::uint16_t>(v, u);
      if (d == 0) continue;
      ++valid;
      sum += d;
      sum_sq += d * d;
    }
  }
  const double total = o.width * o.height;
  EXPECT_NEAR(1.0 - valid / total, 0.1, 0.02);
  const double mean = sum / valid;
  const double sigma = std::sqrt(sum_sq / valid - mean * mean);
  EXPECT_NEAR(mean, 3000.0, 1.0);
  EXPECT_NEAR(sigma, (0.002 + 0.002 * 9.0) * 1000.0, 2.0);  // 20 mm at 3 m

  // Beyond max range there is no depth at all.
  const RgbdFrame far = RenderFrom(WallAt(6.0f), o, {});
  EXPECT_EQ(cv::countNonZero(far.depth_mm), 0);
}

TEST(CastScanTest, RangesInASquareRoom) {
  TriangleMesh room;
  const Eigen::Vector3f grey(0.5f, 0.5f, 0.5f);
  room.AddBox({-2.2f, -2.0f, 0.0f}, {-2.0f, 2.0f, 2.0f}, grey);
  room.AddBox({2.0f, -2.0f, 0.0f}, {2.2f, 2.0f, 2.0f}, grey);
  room.AddBox({-2.0f, -2.2f, 0.0f}, {2.0f, -2.0f, 2.0f}, grey);
  room.AddBox({-2.0f, 2.0f, 0.0f}, {2.0f, 2.2f, 2.0f}, grey);
  const RayCaster caster(room);
  SimLaserOptions o;
  o.noise_m = 0.0;
  std::mt19937 rng(1);
  LaserScan scan;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.2);
  CastScan(caster, pose, o, rng, scan);
  ASSERT_EQ(scan.ranges.size(), 360u);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = scan.angle_min_rad + i * scan.angle_increment_rad;
    const double c = std::cos(a);
    const double s = std::sin(a);
    // Distance to the nearest wall of the square |x|, |y| <= 2 from (0.5, 0) along (c, s).
    double expected = 1e9;
    if (c > 1e-9) expected = std::min(expected, 1.5 / c);
    if (c < -1e-9) expected = std::min(expected, -2.5 / c);
    if (std::abs(s) > 1e-9) expected = std::min(expected, 2.0 / std::abs(s));
    EXPECT_NEAR(scan.ranges[i], expected, 1e-3) << "beam " << i;
  }
}

}  // namespace
}  // namespace corridor::drivers::sim
