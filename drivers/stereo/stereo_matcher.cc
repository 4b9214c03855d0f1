#include "drivers/stereo/stereo_matcher.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace corridor::drivers::stereo {

void ValidateMatcherOptions(const StereoMatcherOptions& o) {
  if (o.disparities < 16 || o.disparities > 512 || o.disparities % 16 != 0) {
    throw std::invalid_argument("disparities: a multiple of 16 from 16 to 512, got " + std::to_string(o.disparities));
  }
  if (o.min_disparity_px < -256 || o.min_disparity_px > 256) {
    throw std::invalid_argument("min_disparity_px: from -256 to 256, got " + std::to_string(o.min_disparity_px));
  }
  const bool sgbm = o.kind == MatcherKind::kSemiGlobal;
  const int lo = sgbm ? 1 : 5;
  const int hi = sgbm ? 11 : 51;
  if (o.block_px % 2 == 0 || o.block_px < lo || o.block_px > hi) {
    throw std::invalid_argument("block_px: odd, from " + std::to_string(lo) + " to " + std::to_string(hi) + " for " +
                                (sgbm ? "sgbm" : "bm") + ", got " + std::to_string(o.block_px));
  }
  if (o.uniqueness_percent < 0 || o.uniqueness_percent > 100) {
    throw std::invalid_argument("uniqueness_percent: from 0 to 100");
  }
  if (o.left_right_px < -1 || o.left_right_px > 64) throw std::invalid_argument("left_right_px: from -1 to 64");
  if (o.edge_px < 0 || o.edge_px > 64) throw std::invalid_argument("edge_px: from 0 to 64");
  if (!(o.min_texture >= 0.0 && o.min_texture <= 128.0)) throw std::invalid_argument("min_texture: from 0 to 128");
  if (o.speckle_window_px < 0 || o.speckle_range_px < 0) {
    throw std::invalid_argument("speckle_window_px, speckle_range_px: not negative");
  }
}

StereoMatcher::StereoMatcher(const StereoMatcherOptions& options) : options_(options) {
  ValidateMatcherOptions(options_);
  const StereoMatcherOptions& o = options_;
  if (o.kind == MatcherKind::kSemiGlobal) {
    // Smoothness penalties for grey images as OpenCV's documentation suggests (8 and 32 times the block's area);
    // the single-pass 3-way mode: twice as fast as the 5-direction default here, as accurate on aloe.
    const int area = o.block_px * o.block_px;
    matcher_ = cv::StereoSGBM::create(o.min_disparity_px, o.disparities, o.block_px, 8 * area, 32 * area,
                                      o.left_right_px, 63, o.uniqueness_percent, o.speckle_window_px,
                                      o.speckle_range_px, cv::StereoSGBM::MODE_SGBM_3WAY);
  } else {
    cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(o.disparities, o.block_px);
    bm->setMinDisparity(o.min_disparity_px);
    bm->setUniquenessRatio(o.uniqueness_percent);
    bm->setDisp12MaxDiff(o.left_right_px);
    bm->setSpeckleWindowSize(o.speckle_window_px);
    bm->setSpeckleRange(o.speckle_range_px);
    matcher_ = bm;
  }
}

void StereoMatcher::Compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_px) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size() || left.empty()) {
    throw std::invalid_argument("stereo matching needs two grey images of one size");
  }
  const int pad = options_.pad_left ? std::max(0, options_.min_disparity_px + options_.disparities) : 0;
  if (pad > 0) {
    cv::copyMakeBorder(left, padded_left_, 0, 0, pad, 0, cv::BORDER_REPLICATE);
    cv::copyMakeBorder(right, padded_right_, 0, 0, pad, 0, cv::BORDER_REPLICATE);
    matcher_->compute(padded_left_, padded_right_, fixed_point_);
  } else {
    matcher_->compute(left, right, fixed_point_);
  }
  // Sixteenths of a pixel; below the search range where there is no match.
  const cv::Mat fixed = fixed_point_.colRange(pad, fixed_point_.cols);
  fixed.convertTo(disparity_px, CV_32F, 1.0 / 16.0);
  disparity_px.setTo(std::numeric_limits<float>::quiet_NaN(), fixed < options_.min_disparity_px * 16);
  // A pixel whose match would lie left of the right image's edge (or within edge_px of it) was not seen by the right
  // camera: what the padding gave it is a guess.
  const int edge = options_.edge_px;
  for (int v = 0; v < disparity_px.rows; ++v) {
    float* d = disparity_px.ptr<float>(v);
    for (int u = 0; u < std::min(pad + edge, disparity_px.cols); ++u) {
      if (d[u] > static_cast<float>(u - edge)) d[u] = std::numeric_limits<float>::quiet_NaN();
    }
  }
  if (options_.min_texture > 0.0) {
    // The block's variance, E[I^2] - E[I]^2, against the threshold's square.
    const cv::Size block(options_.block_px, options_.block_px);
    left.convertTo(mean_, CV_32F);
    cv::multiply(mean_, mean_, mean_square_);
    cv::boxFilter(mean_, mean_, CV_32F, block);
    cv::boxFilter(mean_square_, mean_square_, CV_32F, block);
    cv::multiply(mean_, mean_, texture_);
    cv::subtract(mean_square_, texture_, texture_);
    disparity_px.setTo(std::numeric_limits<float>::quiet_NaN(),
                       texture_ < static_cast<float>(options_.min_texture * options_.min_texture));
  }
}

void DisparityToDepth(const cv::Mat& disparity_px, double focal_px, double baseline_m, double min_m, double max_m,
                      cv::Mat& depth_mm) {
  CV_Assert(disparity_px.type() == CV_32FC1);
  depth_mm.create(disparity_px.size(), CV_16UC1);
  const double f_b_mm = focal_px * baseline_m * 1000.0;
  const double min_mm = min_m * 1000.0;
  const double max_mm = std::min(max_m * 1000.0, 65535.0);
  for (int v = 0; v < disparity_px.rows; ++v) {
    const float* d = disparity_px.ptr<float>(v);
    auto* z = depth_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < disparity_px.cols; ++u) {
      const double mm = d[u] > 0.0f ? f_b_mm / d[u] : 0.0;
      z[u] = mm >= min_mm && mm <= max_mm && mm > 0.0 ? static_cast<std::uint16_t>(std::lround(mm)) : 0;
    }
  }
}

DisparityScore ScoreDisparity(const cv::Mat& disparity_px, const cv::Mat& truth_px, double bad_px) {
  CV_Assert(disparity_px.type() == CV_32FC1 && truth_px.type() == CV_32FC1 && disparity_px.size() == truth_px.size());
  DisparityScore score;
  int bad = 0;
  int found = 0;
  for (int v = 0; v < truth_px.rows; ++v) {
    const float* t = truth_px.ptr<float>(v);
    const float* d = disparity_px.ptr<float>(v);
    for (int u = 0; u < truth_px.cols; ++u) {
      if (!(t[u] > 0.0f)) continue;
      ++score.scored;
      if (!std::isfinite(d[u])) {
        ++bad;
        continue;
      }
      ++found;
      if (std::abs(d[u] - t[u]) > bad_px) ++bad;
    }
  }
  if (score.scored > 0) {
    score.bad = static_cast<double>(bad) / score.scored;
    score.density = static_cast<double>(found) / score.scored;
  }
  return score;
}

}  // namespace corridor::drivers::stereo
