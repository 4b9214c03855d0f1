#include "drivers/sim/sim_stereo.h"

#include "testing/stereo_room.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <vector>

namespace corridor::drivers::sim {
namespace {

SimCameraOptions LevelCamera() {
  SimCameraOptions o;  // 320 x 240, 85 degrees across
  o.tilt_deg = 0.0;
  o.mount_x_m = 0.0;
  o.mount_height_m = 0.5;
  return o;
}

// A grey wall across x = wall_x, filling the view, and optionally a box standing before it.
TriangleMesh Scene(float wall_x, float box_x = 0.0f) {
  TriangleMesh mesh;
  mesh.AddBox({wall_x, -10.0f, -10.0f}, {wall_x + 0.2f, 10.0f, 10.0f}, {0.6f, 0.6f, 0.6f});
  if (box_x > 0.0f) mesh.AddBox({box_x, -0.25f, 0.0f}, {box_x + 0.5f, 0.25f, 1.0f}, {0.5f, 0.4f, 0.3f});
  return mesh;
}

RgbdFrame Render(const TriangleMesh& mesh, const SimCameraOptions& camera, const SimStereoOptions& stereo,
                 CameraInfo* info = nullptr) {
  const RayCaster caster(mesh);
  SimStereoCamera pair(caster, camera, stereo);
  if (info != nullptr) *info = pair.info();
  std::mt19937 rng(3);
  RgbdFrame frame;
  pair.Render(Eigen::Isometry3d::Identity(), rng, frame);
  return frame;
}

// The measured depths within the rectangle, and the share of its pixels that have one.
std::vector<double> Depths(const RgbdFrame& frame, const cv::Rect& box, double* density) {
  std::vector<double> depths;
  for (int v = box.y; v < box.y + box.height; ++v) {
    for (int u = box.x; u < box.x + box.width; ++u) {
      const int d = frame.depth_mm.at<std::uint16_t>(v, u);
      if (d > 0) depths.push_back(d);
    }
  }
  *density = static_cast<double>(depths.size()) / box.area();
  return depths;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

TEST(SimStereoTest, ATexturedWallIsMatchedAtItsDistance) {
  SimStereoOptions stereo;
  stereo.enabled = true;
  CameraInfo info;
  const RgbdFrame frame = Render(Scene(2.0f), LevelCamera(), stereo, &info);
  EXPECT_EQ(frame.depth_mm.size(), cv::Size(320, 240));
  EXPECT_EQ(info.camera.width, 320);
  double density = 0.0;
  const std::vector<double> depths = Depths(frame, cv::Rect(80, 60, 160, 120), &density);
  EXPECT_GT(density, 0.9);
  // 10.4 px of disparity at 2 m: semi-global matching's sub-pixel estimate is drawn towards whole pixels by a
  // fifth of one, 40 mm here, so the median is held to a quarter of a pixel and each depth to 0.3 px.
  EXPECT_NEAR(Median(depths), 2000.0, 48.0);
  int close = 0;
  for (double d : depths) close += std::abs(d - 2000.0) < 60.0 ? 1 : 0;
  EXPECT_GT(close, 0.95 * depths.size());
}

// A plain wall gives a stereo camera nothing to match (ASNS's untextured obstacles, Table 12): holes, not wrong depth.
TEST(SimStereoTest, APlainWallGivesHolesNotWrongDepths) {
  SimStereoOptions stereo;
  stereo.enabled = true;
  stereo.texture = 0.0;
  const RgbdFrame frame = Render(Scene(2.0f), LevelCamera(), stereo);
  double density = 0.0;
  const std::vector<double> depths = Depths(frame, cv::Rect(80, 60, 160, 120), &density);
  EXPECT_LT(density, 0.2);
  int wrong = 0;
  for (double d : depths) wrong += std::abs(d - 2000.0) > 200.0 ? 1 : 0;
  EXPECT_LT(wrong, 0.02 * 160 * 120);
}

TEST(SimStereoTest, ABoxBeforeTheWallStandsOutAtItsOwnDistance) {
  SimStereoOptions stereo;
  stereo.enabled = true;
  CameraInfo info;
  const RgbdFrame frame = Render(Scene(4.0f, 1.5f), LevelCamera(), stereo, &info);
  // The box's face, 1.5 m ahead, 0.5 m wide, its top at 1 m: round the image's centre column, below the horizon.
  Eigen::Vector2d top;
  ASSERT_TRUE(info.camera.Project({1.5, 0.0, 0.9}, top));
  double density = 0.0;
  const std::vector<double> box =
      Depths(frame, cv::Rect(static_cast<int>(top.x()) - 15, static_cast<int>(top.y()) + 5, 30, 30), &density);
  EXPECT_GT(density, 0.8);
  EXPECT_NEAR(Median(box), 1500.0, 30.0);
  const std::vector<double> wall = Depths(frame, cv::Rect(10, 10, 40, 40), &density);
  EXPECT_NEAR(Median(wall), 4000.0 / std::cos(0.0), 150.0);
}

TEST(SimStereoTest, TheIdealCalibrationIsTheCamerasOwn) {
  const SimCameraOptions camera = LevelCamera();
  const stereo::StereoCalibration c = IdealStereoCalibration(camera, 0.12);
  EXPECT_DOUBLE_EQ(c.baseline_m(), 0.12);
  EXPECT_EQ(c.image_size, cv::Size(320, 240));
  EXPECT_DOUBLE_EQ(c.left.matrix(0, 0), MakeCameraInfo(camera).camera.fx);
  EXPECT_NEAR(c.left.matrix(1, 1), c.left.matrix(0, 0), 1e-9);  // square pixels: rectification keeps the width
  EXPECT_DOUBLE_EQ(c.left.matrix(0, 2), 159.5);  // pixel indices: the renderer's centre of pixel u is u + 0.5
}

// A room with a floor, walls and boxes, seen from ten poses: against the true depth (the same views rendered by the
// depth sensor without noise), where both cameras see a point its depth is within 4 cm out to 1.5 m in nearly every
// pixel, and where the right camera cannot see it (the pair's shadow, PinholeCamera::stereo) there is almost none
// (a mismatch the checks cannot rule out, which MORP does not read: nav/ground/morp.h).
TEST(SimStereoTest, InARoomTheDepthIsTrueWhereBothCamerasSeeAndAbsentElsewhere) {
  const TriangleMesh mesh = testing::StereoRoom();
  const RayCaster caster(mesh);
  const SimCameraOptions camera;  // 0.3 m up, tilted 10 degrees down
  SimCameraOptions exact = StereoViewOptions(camera);
  exact.noise_a_m = exact.noise_b_per_m = exact.dropout_fraction = 0.0;
  const RgbdRenderer truth(caster, exact);
  SimStereoOptions options;
  options.enabled = true;
  SimStereoCamera pair(caster, camera, options);
  const nav::PinholeCamera& k = pair.info().camera;
  ASSERT_NEAR(k.stereo.focal_baseline_px_m, k.fx * 0.12, 1e-9);
  int near = 0, near_good = 0, shadow = 0, shadow_found = 0;
  std::mt19937 rng(5);
  for (int n = 0; n < 10; ++n) {
    const Eigen::Isometry3d pose = testing::StereoRoomPose(n, 10);
    RgbdFrame stereo, exact_frame;
    pair.Render(pose, rng, stereo);
    truth.Render(pose * k.base_T_camera, rng, exact_frame);
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const double z = exact_frame.depth_mm.at<std::uint16_t>(v, u) * 1e-3;
        const double measured = stereo.depth_mm.at<std::uint16_t>(v, u) * 1e-3;
        if (z <= 0.3) continue;
        if (!k.stereo.Sees(u + 2.0, z)) {  // two pixels into the shadow
          ++shadow;
          shadow_found += measured > 0.0 ? 1 : 0;
        } else if (z >= 0.5 && z <= 1.5 && measured > 0.0) {
          ++near;
          near_good += std::abs(measured - z) <= 0.04 ? 1 : 0;
        }
      }
    }
  }
  ASSERT_GT(near, 100000);
  EXPECT_GT(near_good, 0.97 * near);
  ASSERT_GT(shadow, 10000);
  EXPECT_LT(shadow_found, 0.03 * shadow);
}

}  // namespace
}  // namespace corridor::drivers::sim
