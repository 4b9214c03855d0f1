#include "drivers/stereo/multi_baseline.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>

namespace corridor::drivers::stereo {
namespace {

// One pixel's fused depth (mm) from the two pairs' readings (mm, 0: none): 174 px cameras, 12 and 24 cm apart.
int Fused(int narrow_mm, int wide_mm, const BaselineFusionOptions& options = {}) {
  const cv::Mat narrow(1, 1, CV_16UC1, cv::Scalar(narrow_mm));
  const cv::Mat wide(1, 1, CV_16UC1, cv::Scalar(wide_mm));
  cv::Mat fused;
  FuseBaselines(narrow, wide, 174.0, 0.12, 0.24, options, fused);
  return fused.at<std::uint16_t>(0, 0);
}

TEST(MultiBaselineTest, EachPairKeepsItsOwnBand) {
  // Near: the narrow pair's, whatever the wide one reads (out of its search, it may mismatch to something farther).
  EXPECT_EQ(Fused(800, 0), 800);
  EXPECT_EQ(Fused(800, 3000), 800);
  // Far: the wide pair's; the narrow pair's reading beyond its band is not kept.
  EXPECT_EQ(Fused(0, 3500), 3500);
  EXPECT_EQ(Fused(3600, 3500), 3500);
  EXPECT_EQ(Fused(3600, 0), 0);
}

TEST(MultiBaselineTest, InTheOverlapBothPairsMustReadItAndAgree) {
  EXPECT_EQ(Fused(1600, 0), 0);
  EXPECT_EQ(Fused(0, 1600), 0);
  // At 1.6 m the narrow pair's sigma is 3.1 cm, the wide one's 1.5 cm: 3 sigmas of their difference is 10 cm.
  const int agreed = Fused(1640, 1600);
  EXPECT_GT(agreed, 1600);
  EXPECT_LT(agreed, 1610);  // weighted four to one towards the wide pair
  EXPECT_EQ(Fused(1800, 1600), 0);
  // A wide reading beyond the overlap against a narrow one within it: one of them mismatched.
  EXPECT_EQ(Fused(1500, 2600), 0);
}

TEST(MultiBaselineTest, BandsThatMeetWithoutOverlapHandOverAtOneDistance) {
  BaselineFusionOptions options;
  options.far_min_m = options.near_max_m = 1.5;
  EXPECT_EQ(Fused(1400, 0, options), 1400);
  EXPECT_EQ(Fused(0, 1600, options), 1600);
  EXPECT_EQ(Fused(1600, 0, options), 0);
  EXPECT_EQ(Fused(0, 1400, options), 0);
}

TEST(MultiBaselineTest, OptionsThatCannotWorkAreRefused) {
  BaselineFusionOptions options;
  options.far_min_m = 2.5;  // above near_max_m
  EXPECT_THROW(ValidateBaselineFusionOptions(options), std::invalid_argument);
  options = {};
  options.agree_sigmas = 0.0;
  EXPECT_THROW(ValidateBaselineFusionOptions(options), std::invalid_argument);
  EXPECT_NO_THROW(ValidateBaselineFusionOptions(BaselineFusionOptions{}));
}

}  // namespace
}  // namespace corridor::drivers::stereo
