#include "drivers/stereo/stereo_calibration.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "testing/opencv_stereo_pairs.h"

namespace corridor::drivers::stereo {
namespace {

using testing::OpenCvStereoPairs;
using Views = testing::StereoViews;

const Views& RealViews() {
  const Views& views = OpenCvStereoPairs();
  for (const cv::Mat& image : views.left) EXPECT_FALSE(image.empty()) << "opencv-doc's stereo pairs";
  return views;
}

const StereoCalibration& RealCalibration() {
  static const StereoCalibration calibration = CalibrateStereo(RealViews().left, RealViews().right, Chessboard{});
  return calibration;
}

TEST(StereoCalibrationTest, RealPairsCalibrateAsOpenCvsOwnSampleDid) {
  std::vector<ViewReport> reports;
  const StereoCalibration c = CalibrateStereo(RealViews().left, RealViews().right, Chessboard{}, &reports);
  ASSERT_EQ(reports.size(), 13u);
  for (const ViewReport& r : reports) EXPECT_TRUE(r.used) << r.why_not;
  EXPECT_EQ(c.views, 13);
  EXPECT_EQ(c.image_size, cv::Size(640, 480));
  EXPECT_LT(c.rms_px, 0.4);  // 0.28 px
  // OpenCV's own results on the same views: its stereo sample (intrinsics.yml) found both focal lengths 534.8 px; its
  // calibration sample, the left camera alone (left_intrinsics.yml), a focal length of 535.9 px and the principal point
  // (342.3, 235.6). The principal point is what views of a board fix least: the stereo sample, which forces both
  // cameras to one focal length, put the left one at (335.7, 240.7); rectification, below, checks ours.
  for (const CameraModel* camera : {&c.left, &c.right}) {
    EXPECT_NEAR(camera->matrix(0, 0), 535.0, 535.0 * 0.01);
    EXPECT_NEAR(camera->matrix(1, 1), 535.0, 535.0 * 0.01);
  }
  EXPECT_NEAR(c.left.matrix(0, 2), 342.3, 3.0);
  EXPECT_NEAR(c.left.matrix(1, 2), 235.6, 3.0);
  // Side by side: the right camera to the right of the left one, a few centimetres away.
  EXPECT_LT(c.translation_m[0], 0.0);
  EXPECT_GT(std::abs(c.translation_m[0]), 5.0 * std::hypot(c.translation_m[1], c.translation_m[2]));
}

// The rectified pair's rows are epipolar lines, and disparity gives metric depth: the board's corners, found again in
// the rectified images and triangulated from their disparities, lie a square's side apart.
TEST(StereoCalibrationTest, RectifiedCornersShareRowsAndTriangulateToTheBoardsSquares) {
  const StereoCalibration& c = RealCalibration();
  const StereoRectification rect = Rectify(c);
  EXPECT_NEAR(rect.baseline_m, c.baseline_m(), 1e-9);
  EXPECT_GT(rect.valid.area(), 0.6 * c.image_size.area());
  const Chessboard board;
  double row_error = 0.0;
  double worst_square_error = 0.0;
  int corners = 0;
  for (std::size_t i = 0; i < RealViews().left.size(); ++i) {
    cv::Mat left;
    cv::Mat right;
    cv::remap(RealViews().left[i], left, rect.left_map_x, rect.left_map_y, cv::INTER_LINEAR);
    cv::remap(RealViews().right[i], right, rect.right_map_x, rect.right_map_y, cv::INTER_LINEAR);
    const std::vector<cv::Point2f> l = FindChessboard(left, board);
    std::vector<cv::Point2f> r = FindChessboard(right, board);
    if (l.empty() || r.empty()) continue;  // the board partly outside the rectified view
    if ((l.back() - l.front()).dot(r.back() - r.front()) < 0.0f) std::reverse(r.begin(), r.end());
    std::vector<cv::Point3d> points;
    for (std::size_t k = 0; k < l.size(); ++k) {
      row_error += std::abs(l[k].y - r[k].y);
      ++corners;
      const double d = l[k].x - r[k].x;
      ASSERT_GT(d, 0.0);
      const double z = rect.focal_px * rect.baseline_m / d;
      points.emplace_back((l[k].x - rect.principal_px.x) * z / rect.focal_px,
                          (l[k].y - rect.principal_px.y) * z / rect.focal_px, z);
    }
    double sum = 0.0;  // neighbours along the board's rows
    int n = 0;
    for (int row = 0; row < board.inner_corners.height; ++row) {
      for (int col = 0; col + 1 < board.inner_corners.width; ++col) {
        const int k = row * board.inner_corners.width + col;
        sum += cv::norm(points[k + 1] - points[k]);
        ++n;
      }
    }
    worst_square_error = std::max(worst_square_error, std::abs(sum / n - board.square_m));
  }
  EXPECT_GE(corners, 10 * 54);
  EXPECT_LT(row_error / corners, 0.25);                   // pixels between the rows a corner is seen on (0.11)
  EXPECT_LT(worst_square_error, 0.015 * board.square_m);  // every view's mean square within 1.5 % (0.6 %)
}

TEST(StereoCalibrationTest, PairsWithoutTheWholeBoardAreLeftOutAndSaidSo) {
  Views views = RealViews();
  views.right[2] = cv::Mat(480, 640, CV_8UC1, cv::Scalar(128));  // the right camera covered
  cv::Mat half = views.left[5].clone();
  half(cv::Rect(0, 0, 640, 240)).setTo(0);  // half the board hidden
  views.left[5] = half;
  std::vector<ViewReport> reports;
  const StereoCalibration c = CalibrateStereo(views.left, views.right, Chessboard{}, &reports);
  EXPECT_EQ(c.views, 11);
  EXPECT_FALSE(reports[2].used);
  EXPECT_EQ(reports[2].why_not, "no whole board in the right image");
  EXPECT_FALSE(reports[5].used);
  EXPECT_EQ(reports[5].why_not, "no whole board in the left image");
  EXPECT_LT(c.rms_px, 0.5);
}

TEST(StereoCalibrationTest, WhatCannotCalibrateIsAClearError) {
  const Views& views = RealViews();
  const std::vector<cv::Mat> three_left(views.left.begin(), views.left.begin() + 3);
  const std::vector<cv::Mat> three_right(views.right.begin(), views.right.begin() + 3);
  try {
    CalibrateStereo(three_left, three_right, Chessboard{});
    FAIL() << "three views calibrated";
  } catch (const StereoCalibrationError& e) {
    EXPECT_STREQ(e.what(), "the whole board is in both images of 3 pairs: calibration needs at least 5");
  }
  std::vector<cv::Mat> mixed = views.right;
  cv::resize(mixed[4], mixed[4], cv::Size(320, 240));
  EXPECT_THROW(CalibrateStereo(views.left, mixed, Chessboard{}), StereoCalibrationError);
  EXPECT_THROW(CalibrateStereo(views.left, three_right, Chessboard{}), StereoCalibrationError);
  // Another board: the views do not show a 7 x 5 board's corners.
  const std::vector<cv::Mat> five_left(views.left.begin(), views.left.begin() + 5);
  const std::vector<cv::Mat> five_right(views.right.begin(), views.right.begin() + 5);
  std::vector<ViewReport> reports;
  EXPECT_THROW(CalibrateStereo(five_left, five_right, Chessboard{{7, 5}, 0.03}, &reports), StereoCalibrationError);
  ASSERT_EQ(reports.size(), 5u);
  EXPECT_EQ(reports[0].why_not, "no whole board in either image");
}

class StereoCalibrationFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("stereo_calibration_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  std::filesystem::path dir_;
};

TEST_F(StereoCalibrationFileTest, SavedCalibrationReadsBackTheSame) {
  StereoCalibration c;
  c.image_size = {640, 480};
  c.left.matrix = {530, 0, 320, 0, 531, 240, 0, 0, 1};
  c.left.distortion = {-0.2, 0.05, 0.001, -0.002, 0.01};
  c.right.matrix = {528, 0, 322, 0, 529, 238, 0, 0, 1};
  c.right.distortion = {-0.1, 0.02, 0.0, 0.0, 0.0};
  cv::Rodrigues(cv::Vec3d(0.01, -0.02, 0.003), c.rotation);
  c.translation_m = {-0.12, 0.001, 0.002};
  c.rms_px = 0.21;
  c.views = 13;
  SaveStereoCalibration(dir_ / "pair.yaml", c);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "pair.yaml.tmp"));
  const StereoCalibration back = LoadStereoCalibration(dir_ / "pair.yaml");
  EXPECT_EQ(back.image_size, c.image_size);
  EXPECT_LT(cv::norm(cv::Mat(back.left.matrix), cv::Mat(c.left.matrix)), 1e-9);
  EXPECT_LT(cv::norm(cv::Mat(back.right.distortion), cv::Mat(c.right.distortion)), 1e-12);
  EXPECT_LT(cv::norm(cv::Mat(back.rotation), cv::Mat(c.rotation)), 1e-12);
  EXPECT_LT(cv::norm(back.translation_m - c.translation_m), 1e-12);
  EXPECT_DOUBLE_EQ(back.rms_px, 0.21);
  EXPECT_EQ(back.views, 13);
}

TEST_F(StereoCalibrationFileTest, BrokenFilesAreClearErrors) {
  const auto message = [](const std::filesystem::path& file) {
    try {
      LoadStereoCalibration(file);
    } catch (const StereoCalibrationError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  EXPECT_EQ(message(dir_ / "none.yaml"), (dir_ / "none.yaml").string() + ": no such file");
  EXPECT_NE(message(Write("garbage.yaml", "\x01\x02{{{ not: [yaml")).find("garbage.yaml: "), std::string::npos);
  EXPECT_EQ(message(Write("empty.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n")),
            (dir_ / "empty.yaml").string() + ": left_camera_matrix must be a 3 x 3 matrix");
  StereoCalibration c;
  c.image_size = {640, 480};
  c.translation_m = {-0.1, 0, 0};
  c.rotation = cv::Matx33d(1, 0, 0, 0, 1, 0, 0, 0, 2);  // scales, does not rotate
  SaveStereoCalibration(dir_ / "scaled.yaml", c);
  EXPECT_EQ(message(dir_ / "scaled.yaml"), (dir_ / "scaled.yaml").string() + ": rotation is not a rotation matrix");
  c.rotation = cv::Matx33d::eye();
  c.translation_m = {0, 0, 0};
  SaveStereoCalibration(dir_ / "one_place.yaml", c);
  EXPECT_EQ(message(dir_ / "one_place.yaml"),
            (dir_ / "one_place.yaml").string() + ": translation_m puts both cameras at one place");
  EXPECT_THROW(SaveStereoCalibration(dir_ / "no" / "such" / "dir.yaml", c), StereoCalibrationError);
}

}  // namespace
}  // namespace corridor::drivers::stereo
