// Calibration of a stereo pair from views of a chessboard: each camera's intrinsics and lens distortion, the right
// camera's pose in the left's, and the rectification that turns the pair's epipolar lines into image rows. Zhang's
// method (IEEE PAMI 2000) with Brown's distortion model (k1, k2, p1, p2, k3), as OpenCV's calib3d implements it:
// corners by findChessboardCornersSB, each camera alone by calibrateCamera, then both refined together by
// stereoCalibrate, rectified by stereoRectify (Bouguet's method).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace corridor::drivers::stereo {

// The calibration target: a printed chessboard, counted by its inner corners (where four squares meet).
struct Chessboard {
  cv::Size inner_corners{9, 6};  // across, down
  double square_m = 0.025;       // one square's side
};

// One camera's pinhole model: x_px = K * distort(X / Z).
struct CameraModel {
  cv::Matx33d matrix = cv::Matx33d::eye();  // K: fx, fy, cx, cy in pixels
  cv::Vec<double, 5> distortion{};          // k1, k2, p1, p2, k3
};

// A calibrated pair. Frames: the left camera's optical frame (x right, y down, z forward) is the pair's frame; a
// point X in it is R * X + T in the right camera's.
struct StereoCalibration {
  cv::Size image_size;  // both cameras'
  CameraModel left;
  CameraModel right;
  cv::Matx33d rotation = cv::Matx33d::eye();  // R
  cv::Vec3d translation_m{};                  // T (a side-by-side pair: about (-baseline, 0, 0))
  double rms_px = 0.0;                        // reprojection error over every corner of every view, both cameras
  int views = 0;                              // pairs that showed the whole board in both images

  double baseline_m() const { return cv::norm(translation_m); }
};

// What became of one pair of images in a calibration.
struct ViewReport {
  bool used = false;
  std::string why_not;  // when not used: which image did not show the whole board
};

// A calibration that cannot be made or a file that does not hold one; the message says which image or key.
class StereoCalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Calibrates from pairs of images taken at the same instant (grey or colour, all one size). A pair in which either
// image does not show the whole board is left out, and `reports` (one a pair, when given) says so. Throws
// StereoCalibrationError when the images differ in size or fewer than `min_views` pairs show the board.
StereoCalibration CalibrateStereo(const std::vector<cv::Mat>& left, const std::vector<cv::Mat>& right,
                                  const Chessboard& board, std::vector<ViewReport>* reports = nullptr,
                                  int min_views = 5);

// The chessboard's inner corners in `image` to a fraction of a pixel, row by row from one corner of the board; empty
// when the whole board is not seen.
std::vector<cv::Point2f> FindChessboard(const cv::Mat& image, const Chessboard& board);

// Writes `calibration` to `file` (OpenCV's YAML storage, readable by its tools), atomically: the file holds the old
// calibration or the new one, never a torn one. StereoCalibrationError when it cannot be written.
void SaveStereoCalibration(const std::filesystem::path& file, const StereoCalibration& calibration);

// Reads a file written by SaveStereoCalibration; StereoCalibrationError naming the file and the key that is missing
// or wrong.
StereoCalibration LoadStereoCalibration(const std::filesystem::path& file);

// The maps that rectify each camera's image (for cv::remap) and the rectified pair's geometry: both images then share
// `focal_px` and `principal_px`, a point seen at column u in the left image is at u - d in the right, at depth
// focal_px * baseline_m / d.
struct StereoRectification {
  cv::Mat left_map_x, left_map_y;
  cv::Mat right_map_x, right_map_y;
  double focal_px = 0.0;
  cv::Point2d principal_px;
  double baseline_m = 0.0;
  cv::Matx33d left_rotation = cv::Matx33d::eye();  // the left camera's frame to the rectified left frame
  cv::Rect valid;                                  // where both rectified images have pixels from their cameras
};

// `alpha` as stereoRectify's: 0 crops the rectified images to valid pixels only, 1 keeps every source pixel.
StereoRectification Rectify(const StereoCalibration& calibration, double alpha = 0.0);

}  // namespace corridor::drivers::stereo
