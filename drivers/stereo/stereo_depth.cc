#include "drivers/stereo/stereo_depth.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace corridor::drivers::stereo {
namespace {

cv::Size OutputSize(const cv::Size& input, int width) {
  return {width, static_cast<int>(std::lround(static_cast<double>(input.height) * width / input.width))};
}

}  // namespace

void ValidateStereoDepthOptions(const StereoDepthOptions& o) {
  if (o.width < 64 || o.width > 4096) throw std::invalid_argument("width: from 64 to 4096 px");
  if (!(o.alpha >= 0.0 && o.alpha <= 1.0)) throw std::invalid_argument("alpha: from 0 to 1");
  if (!(o.min_range_m > 0.0 && o.max_range_m > o.min_range_m && o.max_range_m <= 65.0)) {
    throw std::invalid_argument("min_range_m, max_range_m: 0 < min < max <= 65 m");
  }
  ValidateMatcherOptions(o.matcher);
}

StereoDepth::StereoDepth(const StereoCalibration& calibration, const Eigen::Isometry3d& base_T_left,
                         const StereoDepthOptions& options)
    : options_((ValidateStereoDepthOptions(options), options)),
      input_size_(calibration.image_size),
      output_size_(OutputSize(calibration.image_size, options.width)),
      rectification_(Rectify(calibration, options.alpha)),
      matcher_(options.matcher) {
  if (options.width > input_size_.width) {
    throw std::invalid_argument("width: at most the cameras' " + std::to_string(input_size_.width) + " px");
  }
  // Resizing by s puts pixel centre u at (u + 0.5) s - 0.5.
  const double s = static_cast<double>(output_size_.width) / input_size_.width;
  nav::PinholeCamera& k = info_.camera;
  k.width = output_size_.width;
  k.height = output_size_.height;
  k.fx = k.fy = rectification_.focal_px * s;
  k.cx = (rectification_.principal_px.x + 0.5) * s - 0.5;
  k.cy = (rectification_.principal_px.y + 0.5) * s - 0.5;
  // The rectified frame is the left camera's turned by the rectification: X_rectified = R1 X_left.
  Eigen::Matrix3d left_R_rectified;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) left_R_rectified(r, c) = rectification_.left_rotation(c, r);
  }
  k.base_T_camera = base_T_left;
  k.base_T_camera.linear() = base_T_left.linear() * left_R_rectified;
  k.stereo = {k.fx * rectification_.baseline_m, static_cast<double>(options.matcher.edge_px)};
  info_.min_range_m = options.min_range_m;
  info_.max_range_m = options.max_range_m;
}

void StereoDepth::RectifyAndScale(const cv::Mat& image, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& out) {
  cv::remap(image, rectified_, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  if (output_size_ == input_size_) {
    rectified_.copyTo(out);
  } else {
    cv::resize(rectified_, out, output_size_, 0.0, 0.0, cv::INTER_AREA);  // averages: no aliasing for the matcher
  }
}

void StereoDepth::Process(const cv::Mat& left, const cv::Mat& right, RgbdFrame& frame) {
  for (const cv::Mat* image : {&left, &right}) {
    if (image->size() != input_size_ || (image->type() != CV_8UC1 && image->type() != CV_8UC3)) {
      throw std::invalid_argument("stereo: images of " + std::to_string(input_size_.width) + " x " +
                                  std::to_string(input_size_.height) + " px, grey or BGR, expected; got " +
                                  std::to_string(image->cols) + " x " + std::to_string(image->rows));
    }
  }
  RectifyAndScale(left, rectification_.left_map_x, rectification_.left_map_y, left_);
  RectifyAndScale(right, rectification_.right_map_x, rectification_.right_map_y, right_);
  if (left_.channels() == 3) {
    cv::cvtColor(left_, left_grey_, cv::COLOR_BGR2GRAY);
    frame.color_bgr = left_.clone();
  } else {
    left_grey_ = left_;
    cv::cvtColor(left_, frame.color_bgr, cv::COLOR_GRAY2BGR);
  }
  if (right_.channels() == 3) {
    cv::cvtColor(right_, right_grey_, cv::COLOR_BGR2GRAY);
  } else {
    right_grey_ = right_;
  }
  matcher_.Compute(left_grey_, right_grey_, disparity_);
  const nav::PinholeCamera& k = info_.camera;
  DisparityToDepth(disparity_, k.fx, rectification_.baseline_m, options_.min_range_m, options_.max_range_m,
                   frame.depth_mm);
}

}  // namespace corridor::drivers::stereo
