#include "drivers/stereo/stereo_matcher.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace corridor::drivers::stereo {
namespace {

// A rectified pair of a textured wall facing the cameras: every pixel `d` px apart in the two images.
void Wall(int d, cv::Mat& left, cv::Mat& right) {
  cv::theRNG().state = 7;
  cv::Mat texture(240, 320 + d, CV_8UC1);
  cv::randu(texture, 0, 255);
  cv::GaussianBlur(texture, texture, cv::Size(3, 3), 0.8);  // a camera's blur: texture, not noise alone
  left = texture.colRange(0, 320).clone();  // texture column c: at c in the left image, c - d in the right
  right = texture.colRange(d, d + 320).clone();
}

TEST(StereoMatcherTest, AWallAtOneDistanceGivesOneDisparityAndItsDepth) {
  cv::Mat left;
  cv::Mat right;
  Wall(20, left, right);
  for (MatcherKind kind : {MatcherKind::kSemiGlobal, MatcherKind::kBlock}) {
    StereoMatcherOptions o;
    o.kind = kind;
    o.block_px = kind == MatcherKind::kBlock ? 9 : 5;
    StereoMatcher matcher(o);
    cv::Mat disparity;
    matcher.Compute(left, right, disparity);
    ASSERT_EQ(disparity.size(), left.size());
    ASSERT_EQ(disparity.type(), CV_32FC1);
    int found = 0;
    int right_value = 0;
    for (int v = 10; v < 230; ++v) {
      for (int u = 10; u < 310; ++u) {
        const float d = disparity.at<float>(v, u);
        if (!std::isfinite(d)) continue;
        ++found;
        if (std::abs(d - 20.0f) <= 0.25f) ++right_value;
      }
    }
    EXPECT_GT(found, 0.95 * 220 * 300) << static_cast<int>(kind);
    EXPECT_GT(right_value, 0.98 * found) << static_cast<int>(kind);
    // f = 400 px, baseline 0.12 m: 20 px is 2.4 m.
    cv::Mat depth;
    DisparityToDepth(disparity, 400.0, 0.12, 0.3, 5.0, depth);
    EXPECT_EQ(depth.type(), CV_16UC1);
    EXPECT_NEAR(depth.at<std::uint16_t>(120, 160), 2400, 30);
  }
}

TEST(StereoMatcherTest, PaddingMatchesTheLeftImagesFirstColumnsToo) {
  cv::Mat left;
  cv::Mat right;
  Wall(12, left, right);
  StereoMatcherOptions o;
  cv::Mat padded;
  StereoMatcher(o).Compute(left, right, padded);
  o.pad_left = false;
  cv::Mat plain;
  StereoMatcher(o).Compute(left, right, plain);
  const auto found = [](const cv::Mat& d) {
    int n = 0;
    for (int v = 10; v < 230; ++v) {
      for (int u = 20; u < 60; ++u) n += std::isfinite(d.at<float>(v, u)) ? 1 : 0;
    }
    return n;
  };
  // Columns 20-60: in the search range's band (64 px) that an unpadded matcher cannot match, but seen by both cameras.
  EXPECT_EQ(found(plain), 0);
  EXPECT_GT(found(padded), 0.95 * 220 * 40);
}

TEST(StereoMatcherTest, DepthKeepsOnlyItsRange) {
  cv::Mat disparity = (cv::Mat_<float>(1, 5) << std::numeric_limits<float>::quiet_NaN(), 0.0f, 4.0f, 40.0f, 400.0f);
  cv::Mat depth;
  DisparityToDepth(disparity, 500.0, 0.1, 0.3, 5.0, depth);  // 50 px.m: 12.5 m, 1.25 m, 0.125 m
  EXPECT_EQ(depth.at<std::uint16_t>(0, 0), 0);
  EXPECT_EQ(depth.at<std::uint16_t>(0, 1), 0);
  EXPECT_EQ(depth.at<std::uint16_t>(0, 2), 0);
  EXPECT_EQ(depth.at<std::uint16_t>(0, 3), 1250);
  EXPECT_EQ(depth.at<std::uint16_t>(0, 4), 0);
}

TEST(StereoMatcherTest, ScoreCountsMissingAsBadAndSkipsUnknownTruth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const cv::Mat truth = (cv::Mat_<float>(1, 5) << 10.0f, 10.0f, 10.0f, 10.0f, 0.0f);
  const cv::Mat found = (cv::Mat_<float>(1, 5) << 10.5f, 11.5f, nan, 9.0f, 3.0f);
  const DisparityScore score = ScoreDisparity(found, truth);
  EXPECT_EQ(score.scored, 4);
  EXPECT_DOUBLE_EQ(score.bad, 2.0 / 4.0);  // 11.5 is off by more than 1 px; NaN is missing
  EXPECT_DOUBLE_EQ(score.density, 3.0 / 4.0);
}

TEST(StereoMatcherTest, BadOptionsAndImagesAreClearErrors) {
  const auto message = [](StereoMatcherOptions o) {
    try {
      ValidateMatcherOptions(o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("valid");
  };
  StereoMatcherOptions o;
  EXPECT_EQ(message(o), "valid");
  o.disparities = 50;
  EXPECT_EQ(message(o), "disparities: a multiple of 16 from 16 to 512, got 50");
  o = {};
  o.block_px = 4;
  EXPECT_EQ(message(o), "block_px: odd, from 1 to 11 for sgbm, got 4");
  o.kind = MatcherKind::kBlock;
  o.block_px = 3;
  EXPECT_EQ(message(o), "block_px: odd, from 5 to 51 for bm, got 3");
  StereoMatcher matcher{StereoMatcherOptions{}};
  cv::Mat disparity;
  EXPECT_THROW(matcher.Compute(cv::Mat(240, 320, CV_8UC1), cv::Mat(240, 321, CV_8UC1), disparity),
               std::invalid_argument);
  EXPECT_THROW(matcher.Compute(cv::Mat(240, 320, CV_8UC3), cv::Mat(240, 320, CV_8UC3), disparity),
               std::invalid_argument);
  EXPECT_THROW(matcher.Compute(cv::Mat(), cv::Mat(), disparity), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::stereo
