// Dense matching of a rectified stereo pair, disparity to metric depth, and the Middlebury-style score of a disparity
// image against the truth. The matchers are OpenCV's: semi-global matching (Hirschmüller, IEEE PAMI 2008; OpenCV's
// single-pass "3-way" variant) or block matching (Konolige's), each with its left-right consistency check. They are
// built once, with their buffers, and reused for every frame: ASNS built its matcher each loop, which cost it about a
// second a frame.
#pragma once

#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace corridor::drivers::stereo {

enum class MatcherKind {
  kSemiGlobal,  // SGBM, 3-way: dense and accurate; about 11 ms for 320 x 240 and 112 disparities on one core
  kBlock,       // BM: about half SGBM's time, holes where the texture is poor
};

struct StereoMatcherOptions {
  MatcherKind kind = MatcherKind::kSemiGlobal;
  int min_disparity_px = 0;
  int disparities = 64;         // the search range from min_disparity_px, in pixels; a multiple of 16
  int block_px = 5;             // odd: SGBM 1-11, BM 5-51
  int uniqueness_percent = 10;  // the best cost must beat the second best by this much
  int left_right_px = 1;        // a disparity the right image's match disagrees with by more is dropped; -1: no check
  int speckle_window_px = 100;  // regions of disparity this small are dropped as speckles (0: kept)
  int speckle_range_px = 2;     // ... where neighbours differ by at most this much
  // Pixels whose block in the left image varies less than this (standard deviation, grey levels) get no disparity:
  // on a plain surface a matcher matches the cameras' noise, and what it finds is wrong, not missing (OpenCV's block
  // matcher has such a threshold, its semi-global one none). 0: every pixel is matched.
  double min_texture = 2.5;
  // Match the left image's first `disparities` columns too, by padding both images on the left: otherwise a band as
  // wide as the search range has no disparity at all (on Middlebury's aloe at half size, 13 % of the pixels).
  bool pad_left = true;
  // A pixel whose match lies left of the right image's edge was not seen by the right camera, and one within
  // edge_px of it was matched partly against the padding: both get no disparity (nav::StereoShadow).
  int edge_px = 0;
};

// Throws std::invalid_argument naming the option when `options` cannot build a matcher.
void ValidateMatcherOptions(const StereoMatcherOptions& options);

class StereoMatcher {
 public:
  explicit StereoMatcher(const StereoMatcherOptions& options);
  StereoMatcher(const StereoMatcher&) = delete;
  StereoMatcher& operator=(const StereoMatcher&) = delete;

  // The disparity of each pixel of `left` (CV_32F, pixels; NaN where none was found) from a rectified pair of grey
  // (CV_8UC1) images of one size. Not for concurrent use (the buffers are the matcher's).
  void Compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_px);

  const StereoMatcherOptions& options() const { return options_; }

 private:
  StereoMatcherOptions options_;
  cv::Ptr<cv::StereoMatcher> matcher_;
  cv::Mat padded_left_, padded_right_, fixed_point_;
  cv::Mat mean_, mean_square_, texture_;
};

// Depth along the rectified left camera's axis, z = focal * baseline / d, in millimetres (CV_16UC1, 0 where there
// is no disparity or the depth is outside [min_m, max_m]): the form every depth camera of corridor gives.
void DisparityToDepth(const cv::Mat& disparity_px, double focal_px, double baseline_m, double min_m, double max_m,
                      cv::Mat& depth_mm);

// How far a disparity image is from the truth, as the Middlebury benchmark counts: of the pixels with a true
// disparity, the share whose disparity is off by more than `bad_px` or missing (missing counts as bad), and the share
// that has one at all.
struct DisparityScore {
  double bad = 0.0;
  double density = 0.0;
  int scored = 0;  // pixels with a true disparity
};

// `truth_px` (CV_32F, pixels; 0 or less where unknown) and `disparity_px` as Compute gives it, of one size.
DisparityScore ScoreDisparity(const cv::Mat& disparity_px, const cv::Mat& truth_px, double bad_px = 1.0);

}  // namespace corridor::drivers::stereo
