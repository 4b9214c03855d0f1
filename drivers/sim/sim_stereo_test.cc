#include "drivers/sim/sim_stereo.h"

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
  const RgbdRenderer renderer(caster, camera);
  SimStereoCamera pair(renderer, camera, stereo);
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
  EXPECT_NEAR(Median(depths), 2000.0, 20.0);
  int close = 0;
  for (double d : depths) close += std::abs(d - 2000.0) < 60.0 ? 1 : 0;  // 3 %: a quarter of a pixel's disparity
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
  EXPECT_DOUBLE_EQ(c.left.matrix(0, 2), 159.5);  // pixel indices: the renderer's centre of pixel u is u + 0.5
}

}  // namespace
}  // namespace corridor::drivers::sim
