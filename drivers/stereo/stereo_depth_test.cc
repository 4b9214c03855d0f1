#include "drivers/stereo/stereo_depth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "testing/opencv_stereo_pairs.h"

namespace corridor::drivers::stereo {
namespace {

using testing::OpenCvStereoPairs;

const StereoCalibration& Calibration() {
  static const StereoCalibration c = CalibrateStereo(OpenCvStereoPairs().left, OpenCvStereoPairs().right, Chessboard{});
  return c;
}

// The board's corners in the left camera's frame, from where the left camera alone sees them (the board's pose by
// PnP): what the pair's depth must agree with.
std::vector<Eigen::Vector3d> BoardInLeftCamera(const cv::Mat& left) {
  const Chessboard board;
  const std::vector<cv::Point2f> corners = FindChessboard(left, board);
  std::vector<cv::Point3f> object;
  for (int row = 0; row < board.inner_corners.height; ++row) {
    for (int col = 0; col < board.inner_corners.width; ++col) {
      object.emplace_back(static_cast<float>(col * board.square_m), static_cast<float>(row * board.square_m), 0.0f);
    }
  }
  cv::Vec3d rvec;
  cv::Vec3d tvec;
  EXPECT_TRUE(cv::solvePnP(object, corners, Calibration().left.matrix, Calibration().left.distortion, rvec, tvec));
  cv::Matx33d rotation;
  cv::Rodrigues(rvec, rotation);
  std::vector<Eigen::Vector3d> points;
  for (const cv::Point3f& p : object) {
    const cv::Vec3d x = rotation * cv::Vec3d(p.x, p.y, p.z) + tvec;
    points.emplace_back(x[0], x[1], x[2]);
  }
  return points;
}

// Every real pair through the depth path at the robot's size: where the depth frame has the board's corners (found by
// projecting them through the frame's own camera model and mounting), it has them at the depth the left camera's PnP
// puts them. This checks the rectification's rotation in the mounting, the intrinsics at the frame's size and the
// depth's scale together.
TEST(StereoDepthTest, RealPairsGiveTheBoardsDepthWhereTheFramesCameraSeesIt) {
  const Eigen::Isometry3d base_T_left = nav::CameraMount(0.1, 0.3, 0.2);
  StereoDepthOptions options;
  options.width = 320;
  // The boards are held 0.2-0.45 m from these cameras: 128 disparities at 320 px reach 0.18 m.
  options.matcher.disparities = 128;
  options.min_range_m = 0.15;
  StereoDepth depth(Calibration(), base_T_left, options);
  const nav::PinholeCamera& k = depth.info().camera;
  EXPECT_EQ(k.width, 320);
  EXPECT_EQ(k.height, 240);
  int measured = 0;
  int right = 0;
  double worst_median = 0.0;
  for (std::size_t i = 0; i < OpenCvStereoPairs().left.size(); ++i) {
    RgbdFrame frame;
    depth.Process(OpenCvStereoPairs().left[i], OpenCvStereoPairs().right[i], frame);
    ASSERT_EQ(frame.depth_mm.size(), cv::Size(320, 240));
    ASSERT_EQ(frame.color_bgr.size(), cv::Size(320, 240));
    ASSERT_EQ(frame.color_bgr.type(), CV_8UC3);
    std::vector<double> errors;
    for (const Eigen::Vector3d& corner : BoardInLeftCamera(OpenCvStereoPairs().left[i])) {
      const Eigen::Vector3d base = base_T_left * corner;
      Eigen::Vector2d pixel;
      ASSERT_TRUE(k.Project(base, pixel));
      const int u = static_cast<int>(std::lround(pixel.x()));
      const int v = static_cast<int>(std::lround(pixel.y()));
      if (u < 2 || v < 2 || u >= k.width - 2 || v >= k.height - 2) continue;
      const double z_mm = (k.base_T_camera.inverse() * base).z() * 1000.0;
      // The nearest measured depth round the corner (a corner is an edge between squares, where matching gives some
      // pixels and not others).
      double best = -1.0;
      for (int dv = -2; dv <= 2; ++dv) {
        for (int du = -2; du <= 2; ++du) {
          const double d = frame.depth_mm.at<std::uint16_t>(v + dv, u + du);
          if (d > 0.0 && (best < 0.0 || std::abs(d - z_mm) < std::abs(best - z_mm))) best = d;
        }
      }
      if (best < 0.0) continue;
      ++measured;
      const double error = std::abs(best - z_mm) / z_mm;
      errors.push_back(error);
      if (error < 0.03) ++right;
    }
    if (errors.empty()) continue;
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    worst_median = std::max(worst_median, errors[errors.size() / 2]);
  }
  EXPECT_GT(measured, 0.9 * 13 * 54);  // 689 of the 702 corners
  EXPECT_GT(right, 0.95 * measured);   // 668 within 3 %
  EXPECT_LT(worst_median, 0.01);       // every view's median error 0.11 % or less
}

TEST(StereoDepthTest, TheFramesCameraLooksWhereTheLeftCameraLooks) {
  const Eigen::Isometry3d base_T_left = nav::CameraMount(0.1, 0.3, 0.0);
  StereoDepth depth(Calibration(), base_T_left, StereoDepthOptions{});
  const nav::PinholeCamera& k = depth.info().camera;
  EXPECT_LT((k.base_T_camera.translation() - base_T_left.translation()).norm(), 1e-12);
  // Rectification turns the frame by a degree or two, not more.
  const Eigen::Vector3d forward = k.base_T_camera.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_GT(forward.x(), std::cos(3.0 * M_PI / 180.0));
  EXPECT_DOUBLE_EQ(depth.info().min_range_m, 0.3);
  EXPECT_DOUBLE_EQ(depth.info().max_range_m, 5.0);
}

TEST(StereoDepthTest, BadOptionsAndImagesAreClearErrors) {
  const auto message = [](StereoDepthOptions o) {
    try {
      StereoDepth(Calibration(), Eigen::Isometry3d::Identity(), o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("built");
  };
  StereoDepthOptions o;
  o.width = 1280;
  EXPECT_EQ(message(o), "width: at most the cameras' 640 px");
  o = {};
  o.max_range_m = 0.2;
  EXPECT_EQ(message(o), "min_range_m, max_range_m: 0 < min < max <= 65 m");
  o = {};
  o.matcher.disparities = 60;
  EXPECT_EQ(message(o), "disparities: a multiple of 16 from 16 to 512, got 60");
  StereoDepth depth(Calibration(), Eigen::Isometry3d::Identity(), StereoDepthOptions{});
  RgbdFrame frame;
  EXPECT_THROW(depth.Process(cv::Mat(240, 320, CV_8UC1), cv::Mat(240, 320, CV_8UC1), frame), std::invalid_argument);
  EXPECT_THROW(depth.Process(cv::Mat(480, 640, CV_16UC1), cv::Mat(480, 640, CV_16UC1), frame), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::stereo
