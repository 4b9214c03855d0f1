// What the RealSense driver does with V4L2's buffers and nodes that needs no device: Z16 depth to the camera
// interface's millimetres by the device's depth unit, YUYV colour to BGR, the depth and colour nodes picked out of the
// video nodes by name and formats. Tested on recorded buffers (a real depth frame written as Z16, a colour frame as
// YUYV).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace corridor::drivers::realsense {

// The four-character codes of the formats: V4L2's Z16 (16-bit depth) and YUYV (4:2:2).
inline constexpr std::uint32_t FourCc(char a, char b, char c, char d) {
  return static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b) << 8 | static_cast<std::uint32_t>(c) << 16 |
         static_cast<std::uint32_t>(d) << 24;
}
inline constexpr std::uint32_t kZ16 = FourCc('Z', '1', '6', ' ');
inline constexpr std::uint32_t kYuyv = FourCc('Y', 'U', 'Y', 'V');

// A buffer's rows as the driver gives them: `stride` bytes apart (at least a row's), `bytes` in all. Throws
// std::invalid_argument for a buffer too short for its size.
// Z16 units to millimetres (CV_16UC1, 0 where the camera measured nothing; beyond 65.535 m saturates).
cv::Mat DepthToMillimetres(std::span<const std::uint8_t> bytes, int width, int height, int stride,
                           double depth_scale_m);
// YUYV to BGR (CV_8UC3), resized to `width` x `height` when that differs from the buffer's size.
cv::Mat YuyvToBgr(std::span<const std::uint8_t> bytes, int buffer_width, int buffer_height, int stride, int width,
                  int height);

// A video node as V4L2 describes it: its path, its card name (VIDIOC_QUERYCAP), and the formats it offers.
struct VideoNode {
  std::string path;
  std::string card;
  std::vector<std::uint32_t> formats;
};
struct NodePair {
  std::string depth;
  std::string color;  // empty: none found
};
// The depth node (offering Z16) and the colour node (YUYV, not Z16) of the device whose card name contains `name`;
// none without a depth node. The lowest-numbered of each when a device has several.
std::optional<NodePair> PickNodes(const std::vector<VideoNode>& nodes, const std::string& name);

}  // namespace corridor::drivers::realsense
