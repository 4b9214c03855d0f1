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

// ASNS's wide pair (a third view 24 cm from the left one) fused with the narrow one: beyond 2 m, where the narrow
// pair's depth errors grow, far fewer pixels are more than 4 cm off; near, the narrow pair's depth is as good as alone.
TEST(SimStereoTest, TheWidePairMakesFarDepthTrueAndKeepsTheNearDepth) {
  const TriangleMesh mesh = testing::StereoRoom();
  const RayCaster caster(mesh);
  const SimCameraOptions camera;
  SimCameraOptions exact = StereoViewOptions(camera);
  exact.noise_a_m = exact.noise_b_per_m = exact.dropout_fraction = 0.0;
  const RgbdRenderer truth(caster, exact);
  SimStereoOptions narrow_options;
  narrow_options.enabled = true;
  SimStereoOptions wide_options = narrow_options;
  wide_options.wide_baseline_m = 0.24;
  SimStereoCamera narrow(caster, camera, narrow_options);
  SimStereoCamera wide(caster, camera, wide_options);
  const nav::PinholeCamera& k = narrow.info().camera;
  struct Count {
    int given = 0;
    int off = 0;  // more than 4 cm from the truth
  };
  Count near_narrow, near_wide, far_narrow, far_wide;
  std::mt19937 rng(9);
  for (int n = 0; n < 6; ++n) {
    const Eigen::Isometry3d pose = testing::StereoRoomPose(n, 6);
    RgbdFrame a, b, exact_frame;
    narrow.Render(pose, rng, a);
    wide.Render(pose, rng, b);
    truth.Render(pose * k.base_T_camera, rng, exact_frame);
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const double z = exact_frame.depth_mm.at<std::uint16_t>(v, u) * 1e-3;
        const bool near = z >= 0.5 && z <= 1.5;
        const bool far = z >= 2.5 && z <= 3.5;
        if (!near && !far) continue;
        for (const auto& [frame, count] :
             {std::pair{&a, near ? &near_narrow : &far_narrow}, std::pair{&b, near ? &near_wide : &far_wide}}) {
          const double measured = frame->depth_mm.at<std::uint16_t>(v, u) * 1e-3;
          if (measured <= 0.0) continue;
          ++count->given;
          count->off += std::abs(measured - z) > 0.04 ? 1 : 0;
        }
      }
    }
  }
  ASSERT_GT(far_narrow.given, 10000);
  ASSERT_GT(far_wide.given, far_narrow.given / 2);
  const double far_off_narrow = static_cast<double>(far_narrow.off) / far_narrow.given;
  const double far_off_wide = static_cast<double>(far_wide.off) / far_wide.given;
  // Table 11's 2.5-3.5 m rows: the narrow pair more than half its pixels, the wide one about a third (semi-global
  // matching's sub-pixel estimate is good to about 0.15 px; 4 cm at 3 m is 0.19 px between cameras 24 cm apart).
  EXPECT_LT(far_off_wide, 0.7 * far_off_narrow) << far_off_wide << " against " << far_off_narrow;
  ASSERT_GT(near_wide.given, 0.95 * near_narrow.given);
  EXPECT_LT(near_wide.off, 0.03 * near_wide.given);
}

// A third camera that is not quite in line (turned 3.5 degrees across and half a degree down): the wide pair's own
// rectification differs from the narrow one's by as much, some 10 px, and its depth is carried into the narrow frame's
// pixels before fusing. A box 1.6 m ahead lies in the overlap, where a pixel is kept only when both pairs agree on it:
// not carried, one pixel in seven of the box's would be lost.
TEST(SimStereoTest, AThirdCameraTurnedFromTheRowStillGivesTrueDepth) {
  const TriangleMesh mesh = Scene(3.0f, 1.6f);
  const RayCaster caster(mesh);
  const SimCameraOptions camera = LevelCamera();
  const RgbdRenderer views(caster, StereoViewOptions(camera));
  const stereo::StereoCalibration narrow = IdealStereoCalibration(camera, 0.12);
  stereo::StereoCalibration wide = IdealStereoCalibration(camera, 0.24);
  // The third camera in the left one's frame, q and t; the calibration's R and T take the left frame into its own.
  const Eigen::Matrix3d q =
      (Eigen::AngleAxisd(0.06, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Vector3d t(0.24, 0.0, 0.0);
  const Eigen::Vector3d translation = -(q.transpose() * t);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) wide.rotation(r, c) = q(c, r);
    wide.translation_m[r] = translation[r];
  }
  const Eigen::Isometry3d base_T_left = MakeCameraInfo(camera).camera.base_T_camera;
  stereo::MultiBaselineDepth depth(narrow, wide, base_T_left, SimStereoOptions{}.depth, 64, {});
  std::mt19937 rng(4);
  cv::Mat left, right, third;
  Eigen::Isometry3d left_T_third = Eigen::Isometry3d::Identity();
  left_T_third.linear() = q;
  left_T_third.translation() = t;
  views.RenderColor(base_T_left, 0.5, 2.0, rng, left);
  views.RenderColor(base_T_left * Eigen::Translation3d(0.12, 0.0, 0.0), 0.5, 2.0, rng, right);
  views.RenderColor(base_T_left * left_T_third, 0.5, 2.0, rng, third);
  RgbdFrame frame;
  depth.Process(left, right, third, frame);
  // Of the pixels the narrow pair alone reads at the box's distance, nearly all are kept: the wide pair's reading
  // carried to them agrees. Not carried, those along the box's sides would get the wall behind it, and be dropped.
  stereo::MultiBaselineDepth narrow_only(narrow, std::nullopt, base_T_left, SimStereoOptions{}.depth, 64, {});
  RgbdFrame narrow_frame;
  narrow_only.Process(left, right, cv::Mat(), narrow_frame);
  int box = 0;
  int kept = 0;
  std::vector<double> box_depths;
  for (int v = 0; v < frame.depth_mm.rows; ++v) {
    for (int u = 0; u < frame.depth_mm.cols; ++u) {
      const int n = narrow_frame.depth_mm.at<std::uint16_t>(v, u);
      if (n < 1550 || n > 1650) continue;
      ++box;
      const int fused = frame.depth_mm.at<std::uint16_t>(v, u);
      if (fused > 0) {
        ++kept;
        box_depths.push_back(fused);
      }
    }
  }
  ASSERT_GT(box, 2000);
  EXPECT_GT(kept, 0.97 * box);
  EXPECT_NEAR(Median(box_depths), 1600.0, 20.0);
  double density = 0.0;
  // The wall beside it (on the right: the third camera, turned right, does not see the left edge far off): within 4 cm
  // (the semi-global matcher's sub-pixel estimate is drawn to whole pixels by up to a sixth of one, some 3 cm here).
  const std::vector<double> wall = Depths(frame, cv::Rect(240, 30, 40, 40), &density);
  EXPECT_GT(density, 0.8);
  EXPECT_NEAR(Median(wall), 3000.0, 40.0);
}

}  // namespace
}  // namespace corridor::drivers::sim
