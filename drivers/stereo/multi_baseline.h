// ASNS's two baselines: a camera of three lenses in a row (or a pair and a third camera) matched as two pairs that
// share the left camera, a narrow one (left and middle: 12 cm in ASNS) and a wide one (left and right: 24 cm). The
// narrow pair sees near (its disparities fit a short search); the wide one far, with twice the disparity for a depth
// and so half the error. Fusing them keeps only the depths each pair is trusted for and the two agree on: steps 1 to 4
// of corridor's multi-baseline multi-view filter (MMSVF, docs/asns.md); step 5, over posed frames, is
// nav/ground/multi_view.h.
#pragma once

#include <optional>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "drivers/depth_camera.h"
#include "drivers/stereo/stereo_calibration.h"
#include "drivers/stereo/stereo_depth.h"

namespace corridor::drivers::stereo {

// The two pairs' distance bands. A depth the narrow pair reads nearer than far_min_m is its alone; one the wide pair
// reads beyond near_max_m is the wide pair's alone; between the two (the overlap) a depth is kept only when both
// pairs read it and agree. With far_min_m == near_max_m the bands meet without overlapping.
struct BaselineFusionOptions {
  double near_max_m = 2.0;
  double far_min_m = 1.2;
  // A matched disparity's error (one sigma, pixels): a depth z from focal length f and baseline B is then uncertain by
  // z^2 sigma / (f B). Two readings agree within agree_sigmas of their difference's sigma.
  double disparity_sigma_px = 0.25;
  double agree_sigmas = 3.0;
};

// Throws std::invalid_argument naming the option when `options` cannot work.
void ValidateBaselineFusionOptions(const BaselineFusionOptions& options);

// Fuses the narrow pair's depth and the wide pair's (CV_16UC1 millimetres, 0: none; the same pixels of one camera)
// into `fused_mm`: within the bands above; in the overlap the inverse-variance mean of two readings that agree.
void FuseBaselines(const cv::Mat& narrow_mm, const cv::Mat& wide_mm, double focal_px, double narrow_baseline_m,
                   double wide_baseline_m, const BaselineFusionOptions& options, cv::Mat& fused_mm);

// One pair, or two that share the left camera, as one depth camera. The frames are the narrow pair's: its rectified
// left camera, its colour. The wide pair's depth is matched in its own rectified left camera and brought into the
// narrow one's pixels (the same optical centre, turned by the two rectifications' difference) before fusing.
class MultiBaselineDepth {
 public:
  // `wide`: the left camera with the third one (the left camera's intrinsics as in `narrow`), matched with `options`
  // but `wide_disparities`. Throws std::invalid_argument for unusable options, or a wide pair no wider than the narrow
  // one.
  MultiBaselineDepth(const StereoCalibration& narrow, const std::optional<StereoCalibration>& wide,
                     const Eigen::Isometry3d& base_T_left, const StereoDepthOptions& options, int wide_disparities,
                     const BaselineFusionOptions& fusion);

  const CameraInfo& info() const { return narrow_.info(); }
  bool wide() const { return wide_.has_value(); }

  // The frame of images taken at one instant (as StereoDepth::Process); `third` is ignored without a wide pair.
  void Process(const cv::Mat& left, const cv::Mat& right, const cv::Mat& third, RgbdFrame& frame);

 private:
  // Where each of the narrow frame's pixels is in the wide one, and the depth's scale between them (both empty when
  // the two rectified cameras coincide).
  void BuildAlignment();

  StereoDepth narrow_;
  std::optional<StereoDepth> wide_;
  BaselineFusionOptions fusion_;
  cv::Mat align_x_, align_y_, align_scale_;
  RgbdFrame narrow_frame_, wide_frame_;
  cv::Mat aligned_mm_, scaled_;
};

}  // namespace corridor::drivers::stereo
