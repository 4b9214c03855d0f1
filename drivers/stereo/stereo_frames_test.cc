// The stereo driver's buffers without a device: opencv-doc's real pairs written as a side-by-side UVC camera sends them
// (one MJPEG or YUYV frame holding both views), and the faults USB cameras show (torn and garbage frames).
#include "drivers/stereo/stereo_frames.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drivers/stereo/stereo_depth.h"
#include "testing/opencv_stereo_pairs.h"
#include "testing/yuyv.h"

namespace corridor::drivers::stereo {
namespace {

using testing::OpenCvStereoPairs;

cv::Mat SideBySide(std::size_t pair) {
  cv::Mat grey;
  cv::hconcat(OpenCvStereoPairs().left[pair], OpenCvStereoPairs().right[pair], grey);
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

std::vector<std::uint8_t> Jpeg(const cv::Mat& image, int quality = 90) {
  std::vector<std::uint8_t> bytes;
  cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality});
  return bytes;
}

double MeanDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat grey_a;
  cv::Mat grey_b;
  cv::cvtColor(a, grey_a, cv::COLOR_BGR2GRAY);
  if (b.channels() == 3) {
    cv::cvtColor(b, grey_b, cv::COLOR_BGR2GRAY);
  } else {
    grey_b = b;
  }
  cv::Mat difference;
  cv::absdiff(grey_a, grey_b, difference);
  return cv::mean(difference)[0];
}

TEST(StereoFramesTest, ASideBySideFrameIsTheTwoViewsInMjpegAndYuyv) {
  const cv::Mat frame = SideBySide(0);
  ASSERT_EQ(frame.size(), cv::Size(1280, 480));
  const std::vector<std::uint8_t> jpeg = Jpeg(frame);
  const std::vector<std::uint8_t> yuyv = testing::ToYuyv(frame);
  for (const auto& [format, bytes] : {std::pair{VideoFormat::kMjpeg, jpeg}, std::pair{VideoFormat::kYuyv, yuyv}}) {
    const cv::Mat decoded = DecodeBuffer(bytes, format, 1280, 480, 1280 * 2);
    ASSERT_EQ(decoded.type(), CV_8UC3);
    cv::Mat left;
    cv::Mat right;
    SplitSideBySide(decoded, left, right);
    EXPECT_EQ(left.size(), cv::Size(640, 480));
    EXPECT_LT(MeanDifference(left, OpenCvStereoPairs().left[0]), 2.0);
    EXPECT_LT(MeanDifference(right, OpenCvStereoPairs().right[0]), 2.0);
  }
}

// The views as the camera sends them, compressed, give the depth the raw views give.
TEST(StereoFramesTest, DepthFromMjpegViewsIsTheDepthOfTheRawViews) {
  const StereoCalibration calibration =
      CalibrateStereo(OpenCvStereoPairs().left, OpenCvStereoPairs().right, Chessboard{});
  StereoDepthOptions options;
  options.matcher.disparities = 128;  // boards 0.2-0.45 m away (stereo_depth_test.cc)
  options.min_range_m = 0.15;
  StereoDepth depth(calibration, Eigen::Isometry3d::Identity(), options);
  RgbdFrame raw;
  depth.Process(OpenCvStereoPairs().left[5], OpenCvStereoPairs().right[5], raw);
  const cv::Mat decoded = DecodeBuffer(Jpeg(SideBySide(5)), VideoFormat::kMjpeg, 1280, 480, 0);
  cv::Mat left;
  cv::Mat right;
  SplitSideBySide(decoded, left, right);
  RgbdFrame sent;
  depth.Process(left, right, sent);
  int both = 0;
  int same = 0;
  for (int v = 0; v < raw.depth_mm.rows; ++v) {
    for (int u = 0; u < raw.depth_mm.cols; ++u) {
      const int a = raw.depth_mm.at<std::uint16_t>(v, u);
      const int b = sent.depth_mm.at<std::uint16_t>(v, u);
      if (a == 0 || b == 0) continue;
      ++both;
      if (std::abs(a - b) <= 0.02 * a) ++same;
    }
  }
  EXPECT_GT(both, raw.depth_mm.total() / 4);  // the board fills a good part of the view
  EXPECT_GT(same, 0.95 * both);
}

TEST(StereoFramesTest, TornGarbageAndMisSizedFramesAreRefused) {
  const std::vector<std::uint8_t> jpeg = Jpeg(SideBySide(1));
  const auto refused = [](const std::vector<std::uint8_t>& bytes, int width = 1280) {
    try {
      DecodeBuffer(bytes, VideoFormat::kMjpeg, width, 480, 0);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("decoded");
  };
  // The bus dropped the frame's second half.
  EXPECT_EQ(refused(std::vector<std::uint8_t>(jpeg.begin(), jpeg.begin() + jpeg.size() / 2)),
            "a torn MJPEG frame (no end marker)");
  EXPECT_EQ(refused({}), "an MJPEG buffer that is not a JPEG (0 bytes)");
  std::vector<std::uint8_t> garbage(5000);
  cv::randu(garbage, 0, 256);
  garbage[0] = 0x12;
  EXPECT_EQ(refused(garbage), "an MJPEG buffer that is not a JPEG (5000 bytes)");
  // Markers at both ends and noise between.
  garbage[0] = 0xFF;
  garbage[1] = 0xD8;
  garbage[4998] = 0xFF;
  garbage[4999] = 0xD9;
  EXPECT_EQ(refused(garbage), "an MJPEG frame that does not decode");
  EXPECT_EQ(refused(jpeg, 640), "an MJPEG frame of 1280 x 480 px, not 640 x 480");
  // A YUYV buffer a row short.
  const std::vector<std::uint8_t> yuyv = testing::ToYuyv(SideBySide(1));
  const std::vector<std::uint8_t> short_yuyv(yuyv.begin(), yuyv.end() - 1280 * 2);
  EXPECT_THROW(DecodeBuffer(short_yuyv, VideoFormat::kYuyv, 1280, 480, 1280 * 2), std::invalid_argument);
  cv::Mat left;
  cv::Mat right;
  EXPECT_THROW(SplitSideBySide(cv::Mat(480, 641, CV_8UC3), left, right), std::invalid_argument);
}

TEST(StereoFramesTest, TheSideBySideNodeIsFoundByNameAndFormat) {
  const std::vector<realsense::VideoNode> nodes = {
      {"/dev/video0", "Integrated Camera: Integrated C", {realsense::kYuyv, kMjpg}},
      {"/dev/video12", "3D USB Camera: 3D USB Camera", {kMjpg, realsense::kYuyv}},
      {"/dev/video2", "3D USB Camera: 3D USB Camera", {kMjpg, realsense::kYuyv}},
      {"/dev/video3", "3D USB Camera: 3D USB Camera", {}},  // its metadata node
  };
  EXPECT_EQ(PickStereoNode(nodes, "3D USB", VideoFormat::kMjpeg), "/dev/video2");
  EXPECT_EQ(PickStereoNode(nodes, "Integrated", VideoFormat::kYuyv), "/dev/video0");
  EXPECT_FALSE(PickStereoNode(nodes, "ELP", VideoFormat::kMjpeg));
  EXPECT_FALSE(PickStereoNode({{"/dev/video4", "3D USB Camera", {realsense::kYuyv}}}, "3D USB", VideoFormat::kMjpeg));
}

TEST(StereoFramesTest, TwoCamerasFramesPairOnlyWhenCloseInTime) {
  const TimeNs ms = 1'000'000;
  FrameSet pairer(2, 20 * ms);
  const cv::Mat a(2, 2, CV_8UC3, cv::Scalar::all(1));
  const cv::Mat b(2, 2, CV_8UC3, cv::Scalar::all(2));
  EXPECT_FALSE(pairer.Take());
  pairer.Push(0, 100 * ms, a);
  EXPECT_FALSE(pairer.Take());  // no right frame yet
  pairer.Push(1, 130 * ms, b);
  EXPECT_FALSE(pairer.Take());  // 30 ms apart
  pairer.Push(0, 133 * ms, a);  // the left's newer frame
  const auto pair = pairer.Take();
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->stamp_ns, 130 * ms);
  ASSERT_EQ(pair->images.size(), 2u);
  EXPECT_EQ(pair->images[0].at<cv::Vec3b>(0, 0)[0], 1);
  EXPECT_EQ(pair->images[1].at<cv::Vec3b>(0, 0)[0], 2);
  EXPECT_FALSE(pairer.Take());  // each frame in one pair only
  pairer.Push(1, 166 * ms, b);
  EXPECT_FALSE(pairer.Take());
}

// A pair and a third camera (ASNS's wide baseline): a set only when all three are close in time.
TEST(StereoFramesTest, AThirdCamerasFrameJoinsOnlyWhenAllThreeAreClose) {
  const TimeNs ms = 1'000'000;
  FrameSet set(3, 20 * ms);
  const cv::Mat a(2, 2, CV_8UC3, cv::Scalar::all(1));
  set.Push(0, 100 * ms, a);
  set.Push(1, 105 * ms, a);
  EXPECT_FALSE(set.Take());  // the third has none
  set.Push(2, 125 * ms, a);
  EXPECT_FALSE(set.Take());  // 25 ms from the first
  set.Push(0, 118 * ms, a);
  set.Push(1, 119 * ms, a);
  const auto taken = set.Take();
  ASSERT_TRUE(taken);
  EXPECT_EQ(taken->stamp_ns, 118 * ms);
  EXPECT_EQ(taken->images.size(), 3u);
  EXPECT_FALSE(set.Take());
  EXPECT_THROW(FrameSet(1, ms), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::stereo
