#include "drivers/stereo/multi_baseline.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace corridor::drivers::stereo {
namespace {

StereoDepthOptions WithDisparities(StereoDepthOptions options, int disparities) {
  options.matcher.disparities = disparities;
  return options;
}

// The depth kept for a pixel read `n` metres away by the narrow pair and `w` by the wide one (0: no reading), 0 for
// none. `n_var` and `w_var`: the readings' variances per m^4 (z^2 sigma / (f B), squared, is z^4 times it).
double Fuse(double n, double w, double n_var, double w_var, const BaselineFusionOptions& o) {
  if (n > 0.0 && n < o.far_min_m) return n;  // the narrow pair's own band
  const bool overlap = (n >= o.far_min_m && n <= o.near_max_m) || (w >= o.far_min_m && w <= o.near_max_m);
  if (overlap) {
    // Both pairs must read it and agree (a wide reading beyond the overlap where the narrow pair reads within it is the
    // wide pair's mismatch of something nearer, or the narrow one's of something farther: either way not kept).
    if (n <= 0.0 || w <= 0.0) return 0.0;
    const double z4 = std::pow(0.5 * (n + w), 4);
    const double sn = n_var * z4;
    const double sw = w_var * z4;
    const double d = n - w;
    if (d * d > o.agree_sigmas * o.agree_sigmas * (sn + sw)) return 0.0;
    return (n / sn + w / sw) / (1.0 / sn + 1.0 / sw);
  }
  return w > o.near_max_m ? w : 0.0;  // the wide pair's own band; a narrow reading beyond its band is not kept
}

}  // namespace

void ValidateBaselineFusionOptions(const BaselineFusionOptions& o) {
  if (!(o.far_min_m > 0.0 && o.near_max_m >= o.far_min_m && o.near_max_m < 65.0)) {
    throw std::invalid_argument("near_max_m, far_min_m: 0 < far_min_m <= near_max_m < 65 m");
  }
  if (!(o.disparity_sigma_px > 0.0 && o.disparity_sigma_px <= 10.0)) {
    throw std::invalid_argument("disparity_sigma_px: above 0, at most 10 px");
  }
  if (!(o.agree_sigmas > 0.0 && o.agree_sigmas <= 100.0))
    throw std::invalid_argument("agree_sigmas: above 0, at most 100");
}

void FuseBaselines(const cv::Mat& narrow_mm, const cv::Mat& wide_mm, double focal_px, double narrow_baseline_m,
                   double wide_baseline_m, const BaselineFusionOptions& o, cv::Mat& fused_mm) {
  CV_Assert(narrow_mm.type() == CV_16UC1 && wide_mm.type() == CV_16UC1 && narrow_mm.size() == wide_mm.size());
  const double n_sigma = o.disparity_sigma_px / (focal_px * narrow_baseline_m);
  const double w_sigma = o.disparity_sigma_px / (focal_px * wide_baseline_m);
  fused_mm.create(narrow_mm.size(), CV_16UC1);
  for (int v = 0; v < narrow_mm.rows; ++v) {
    const auto* n_row = narrow_mm.ptr<std::uint16_t>(v);
    const auto* w_row = wide_mm.ptr<std::uint16_t>(v);
    auto* out = fused_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < narrow_mm.cols; ++u) {
      const double z = Fuse(1e-3 * n_row[u], 1e-3 * w_row[u], n_sigma * n_sigma, w_sigma * w_sigma, o);
      out[u] = static_cast<std::uint16_t>(std::lround(1e3 * z));
    }
  }
}

MultiBaselineDepth::MultiBaselineDepth(const StereoCalibration& narrow, const std::optional<StereoCalibration>& wide,
                                       const Eigen::Isometry3d& base_T_left, const StereoDepthOptions& options,
                                       int wide_disparities, const BaselineFusionOptions& fusion)
    : narrow_(narrow, base_T_left, options), fusion_(fusion) {
  if (!wide) return;
  ValidateBaselineFusionOptions(fusion);
  if (wide->image_size != narrow.image_size) throw std::invalid_argument("wide pair: views of the narrow pair's size");
  if (wide->baseline_m() <= narrow.baseline_m()) {
    throw std::invalid_argument("wide pair: its baseline must be longer than the narrow pair's");
  }
  wide_.emplace(*wide, base_T_left, WithDisparities(options, wide_disparities));
  BuildAlignment();
}

void MultiBaselineDepth::BuildAlignment() {
  const nav::PinholeCamera& n = narrow_.info().camera;
  const nav::PinholeCamera& w = wide_->info().camera;
  // Both are the left camera turned by a rectification: the same optical centre, so a pixel's ray maps across exactly.
  const Eigen::Matrix3d w_R_n = w.base_T_camera.linear().transpose() * n.base_T_camera.linear();
  const bool same = w_R_n.isIdentity(1e-9) && n.fx == w.fx && n.fy == w.fy && n.cx == w.cx && n.cy == w.cy &&
                    n.width == w.width && n.height == w.height;
  if (same) return;
  align_x_.create(n.height, n.width, CV_32FC1);
  align_y_.create(n.height, n.width, CV_32FC1);
  align_scale_.create(n.height, n.width, CV_32FC1);
  for (int v = 0; v < n.height; ++v) {
    for (int u = 0; u < n.width; ++u) {
      const Eigen::Vector3d ray_w = w_R_n * Eigen::Vector3d((u - n.cx) / n.fx, (v - n.cy) / n.fy, 1.0);
      const bool ahead = ray_w.z() > 1e-6;
      align_x_.at<float>(v, u) = ahead ? static_cast<float>(w.fx * ray_w.x() / ray_w.z() + w.cx) : -1.0f;
      align_y_.at<float>(v, u) = ahead ? static_cast<float>(w.fy * ray_w.y() / ray_w.z() + w.cy) : -1.0f;
      // A point at depth z along the narrow camera's axis is at z ray_w.z along the wide one's.
      align_scale_.at<float>(v, u) = ahead ? static_cast<float>(1.0 / ray_w.z()) : 0.0f;
    }
  }
}

void MultiBaselineDepth::Process(const cv::Mat& left, const cv::Mat& right, const cv::Mat& third, RgbdFrame& frame) {
  if (!wide_) {
    narrow_.Process(left, right, frame);
    return;
  }
  narrow_.Process(left, right, narrow_frame_);
  wide_->Process(left, third, wide_frame_);
  const cv::Mat* wide_mm = &wide_frame_.depth_mm;
  if (!align_x_.empty()) {
    cv::remap(wide_frame_.depth_mm, aligned_mm_, align_x_, align_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT);
    aligned_mm_.convertTo(scaled_, CV_32FC1);
    cv::multiply(scaled_, align_scale_, scaled_);
    scaled_.convertTo(aligned_mm_, CV_16UC1);
    wide_mm = &aligned_mm_;
  }
  FuseBaselines(narrow_frame_.depth_mm, *wide_mm, narrow_.info().camera.fx, narrow_.baseline_m(),
                wide_->baseline_m() * wide_->info().camera.fx / narrow_.info().camera.fx, fusion_, frame.depth_mm);
  // Moved, not shared: the next pair's colour must not be written into a frame already handed on.
  frame.color_bgr = std::move(narrow_frame_.color_bgr);
}

}  // namespace corridor::drivers::stereo
