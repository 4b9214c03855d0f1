// A calibrated stereo pair as an RGB-D camera: each pair of images rectified, matched and turned into the depth frame
// every depth camera of corridor gives (millimetres along the optical axis, colour of the same size), so that MORP,
// the tracker, the 3D map and localization work with either sensor. The device drivers (a side-by-side UVC camera,
// two UVC cameras) and the simulator's stereo camera all hand their pairs to this one class.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "drivers/depth_camera.h"
#include "drivers/stereo/stereo_calibration.h"
#include "drivers/stereo/stereo_matcher.h"

namespace corridor::drivers::stereo {

struct StereoDepthOptions {
  // The rectified pair is matched, and the frame given, at this width (the height keeps the calibration's aspect):
  // a small robot's board matches 320 x 240 at the camera's rate, 640 x 480 at a quarter of it.
  int width = 320;
  double alpha = 0.0;  // rectification's crop (Rectify): 0 keeps only pixels both cameras see
  StereoMatcherOptions matcher;
  double min_range_m = 0.3;
  double max_range_m = 5.0;  // beyond it a disparity of a few pixels is not depth enough to drive by
};

// Throws std::invalid_argument naming the option when `options` cannot work with `calibration`.
void ValidateStereoDepthOptions(const StereoDepthOptions& options);

class StereoDepth {
 public:
  // Builds the rectification maps and the matcher once. `base_T_left` is the left camera's optical frame in the robot's
  // base frame (its mounting); the frames are given in the rectified left camera's frame, turned from it by the
  // rectification's rotation. Throws std::invalid_argument for unusable options.
  StereoDepth(const StereoCalibration& calibration, const Eigen::Isometry3d& base_T_left,
              const StereoDepthOptions& options);
  StereoDepth(const StereoDepth&) = delete;
  StereoDepth& operator=(const StereoDepth&) = delete;

  // The rectified left camera at the frames' size, where it sits on the base, and the range of depths given.
  const CameraInfo& info() const { return info_; }
  double baseline_m() const { return rectification_.baseline_m; }

  // Depth and colour (the rectified left image) of a pair taken at one instant, grey or BGR at the calibration's size;
  // std::invalid_argument for images of another size. Not for concurrent use.
  void Process(const cv::Mat& left, const cv::Mat& right, RgbdFrame& frame);

 private:
  void RectifyAndScale(const cv::Mat& image, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& out);

  StereoDepthOptions options_;
  cv::Size input_size_;
  cv::Size output_size_;
  StereoRectification rectification_;
  StereoMatcher matcher_;
  CameraInfo info_;
  cv::Mat rectified_, left_, right_, left_grey_, right_grey_, disparity_;
};

}  // namespace corridor::drivers::stereo
