// The RealSense driver's conversions on recorded buffers: a real depth frame (TUM RGB-D, a Kinect's, in the tree) laid
// out as a D4xx's Z16 buffer with padded rows, and a real colour frame written as YUYV. No V4L2 device is needed.
#include "drivers/realsense/v4l2_frames.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>

#include "drivers/realsense/realsense_options.h"
#include "testing/source_dir.h"
#include "testing/yuyv.h"

namespace corridor::drivers::realsense {
namespace {

// The TUM frame in metres (its PNG holds depth times 5000).
cv::Mat TumMetres() {
  const cv::Mat raw =
      cv::imread((testing::SourceDir() / "tests/data/depth/1_depth.png").string(), cv::IMREAD_UNCHANGED);
  cv::Mat metres;
  raw.convertTo(metres, CV_64F, 1.0 / 5000.0);
  return metres;
}

// `metres` as a Z16 buffer in units of `scale_m`, each row padded to `stride` bytes.
std::vector<std::uint8_t> Z16(const cv::Mat& metres, double scale_m, int stride) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(stride) * metres.rows, 0xEE);
  for (int r = 0; r < metres.rows; ++r) {
    for (int c = 0; c < metres.cols; ++c) {
      const auto units = static_cast<std::uint16_t>(std::lround(metres.at<double>(r, c) / scale_m));
      std::memcpy(&bytes[static_cast<std::size_t>(r) * stride + 2 * c], &units, 2);
    }
  }
  return bytes;
}

TEST(V4l2FramesTest, Z16DepthBecomesMillimetresByTheDevicesUnit) {
  const cv::Mat metres = TumMetres();
  ASSERT_EQ(metres.size(), cv::Size(640, 480));
  const int stride = 640 * 2 + 64;  // padded rows, as some drivers lay them out
  // A D435's unit (1 mm): the same numbers.
  const cv::Mat mm = DepthToMillimetres(Z16(metres, 0.001, stride), 640, 480, stride, 0.001);
  ASSERT_EQ(mm.type(), CV_16UC1);
  int holes = 0, checked = 0;
  for (int r = 0; r < 480; r += 7) {
    for (int c = 0; c < 640; c += 5) {
      const double expected = metres.at<double>(r, c) * 1000.0;
      EXPECT_NEAR(mm.at<std::uint16_t>(r, c), expected, 0.5);
      holes += expected == 0.0 ? 1 : 0;
      ++checked;
    }
  }
  EXPECT_GT(holes, checked / 10);  // the Kinect's holes stay 0: no measurement
  // A D405's unit (0.1 mm), whose 16 bits end at 6.5535 m (the frame's farther pixels are left out): scaled, rounded
  // to the millimetre.
  cv::Mat near_metres = metres.clone();
  near_metres.setTo(0.0, metres > 6.5);
  const cv::Mat fine = DepthToMillimetres(Z16(near_metres, 0.0001, stride), 640, 480, stride, 0.0001);
  for (int r = 0; r < 480; r += 11) {
    for (int c = 0; c < 640; c += 13) {
      EXPECT_NEAR(fine.at<std::uint16_t>(r, c), near_metres.at<double>(r, c) * 1000.0, 0.51);
    }
  }
  // A buffer cut short is refused, not read past.
  std::vector<std::uint8_t> cut = Z16(metres, 0.001, stride);
  cut.resize(cut.size() / 2);
  EXPECT_THROW(DepthToMillimetres(cut, 640, 480, stride, 0.001), std::invalid_argument);
  EXPECT_THROW(DepthToMillimetres(cut, 640, 480, 100, 0.001), std::invalid_argument);
}

TEST(V4l2FramesTest, YuyvColourBecomesBgrOfTheDepthsSize) {
  const cv::Mat bgr = cv::imread((testing::SourceDir() / "tests/data/depth/1.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  const std::vector<std::uint8_t> yuyv = testing::ToYuyv(bgr);
  const cv::Mat same = YuyvToBgr(yuyv, bgr.cols, bgr.rows, bgr.cols * 2, bgr.cols, bgr.rows);
  ASSERT_EQ(same.type(), CV_8UC3);
  cv::Mat difference;
  cv::absdiff(same, bgr, difference);
  EXPECT_LT(cv::mean(difference)[0] + cv::mean(difference)[1] + cv::mean(difference)[2], 3 * 6.0);
  // Colour scaled to a depth image of another size.
  const cv::Mat small = YuyvToBgr(yuyv, bgr.cols, bgr.rows, bgr.cols * 2, 320, 240);
  EXPECT_EQ(small.size(), cv::Size(320, 240));
}

TEST(V4l2FramesTest, TheDepthAndColourNodesArePickedByNameAndFormat) {
  const std::vector<VideoNode> nodes = {
      {"/dev/video0", "Integrated Camera: Integrated C", {kYuyv}},
      {"/dev/video10", "Intel(R) RealSense(TM) Depth Ca", {kYuyv}},  // the colour's node
      {"/dev/video2", "Intel(R) RealSense(TM) Depth Ca", {kZ16}},    // the depth's
      {"/dev/video4", "Intel(R) RealSense(TM) Depth Ca", {FourCc('G', 'R', 'E', 'Y'), FourCc('Y', '8', 'I', ' ')}},
      {"/dev/video3", "Intel(R) RealSense(TM) Depth Ca", {kZ16}},  // metadata or a second stream: not the first
  };
  const std::optional<NodePair> pair = PickNodes(nodes, "RealSense");
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->depth, "/dev/video2");
  EXPECT_EQ(pair->color, "/dev/video10");
  EXPECT_FALSE(PickNodes(nodes, "Astra"));
  EXPECT_FALSE(PickNodes({{"/dev/video0", "Integrated Camera", {kYuyv}}}, "Integrated"));  // no depth
}

TEST(V4l2FramesTest, IntrinsicsComeFromACalibrationOrTheFieldsOfView) {
  CameraMountOptions o = RealSenseOptions{}.camera;
  const nav::PinholeCamera fov = ToPinhole(o);
  EXPECT_NEAR(fov.fx, 320.0 / std::tan(43.5 * M_PI / 180.0), 1e-9);
  EXPECT_NEAR(fov.fy, 240.0 / std::tan(29.0 * M_PI / 180.0), 1e-9);
  EXPECT_DOUBLE_EQ(fov.cx, 319.5);
  o.fx = 386.2;
  o.fy = 386.2;
  o.cx = 321.7;
  o.cy = 238.4;
  const nav::PinholeCamera calibrated = ToPinhole(o);
  EXPECT_DOUBLE_EQ(calibrated.fx, 386.2);
  EXPECT_DOUBLE_EQ(calibrated.cy, 238.4);
  // Mounted 0.3 m up, looking forward: the optical axis is the base's x.
  const Eigen::Vector3d axis = calibrated.base_T_camera.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_GT(axis.x(), 0.95);
}

}  // namespace
}  // namespace corridor::drivers::realsense
