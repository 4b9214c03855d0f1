#include "drivers/realsense/v4l2_frames.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace corridor::drivers::realsense {
namespace {

void CheckBuffer(std::span<const std::uint8_t> bytes, int width, int height, int stride, int bytes_per_pixel) {
  if (width <= 0 || height <= 0 || stride < width * bytes_per_pixel ||
      bytes.size() < static_cast<std::size_t>(stride) * static_cast<std::size_t>(height - 1) +
                         static_cast<std::size_t>(width * bytes_per_pixel)) {
    throw std::invalid_argument("a video buffer too short for its size");
  }
}

}  // namespace

cv::Mat DepthToMillimetres(std::span<const std::uint8_t> bytes, int width, int height, int stride,
                           double depth_scale_m) {
  CheckBuffer(bytes, width, height, stride, 2);
  // The buffer's rows as they are; copied (V4L2 takes its buffer back) and scaled unless the unit is 1 mm.
  const cv::Mat raw(height, width, CV_16UC1, const_cast<std::uint8_t*>(bytes.data()), static_cast<std::size_t>(stride));
  cv::Mat mm;
  if (std::abs(depth_scale_m - 0.001) < 1e-12) {
    raw.copyTo(mm);
  } else {
    raw.convertTo(mm, CV_16UC1, depth_scale_m * 1000.0);  // rounds and saturates
  }
  return mm;
}

cv::Mat YuyvToBgr(std::span<const std::uint8_t> bytes, int buffer_width, int buffer_height, int stride, int width,
                  int height) {
  CheckBuffer(bytes, buffer_width, buffer_height, stride, 2);
  const cv::Mat yuyv(buffer_height, buffer_width, CV_8UC2, const_cast<std::uint8_t*>(bytes.data()),
                     static_cast<std::size_t>(stride));
  cv::Mat bgr;
  cv::cvtColor(yuyv, bgr, cv::COLOR_YUV2BGR_YUYV);
  if (bgr.cols != width || bgr.rows != height) cv::resize(bgr, bgr, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  return bgr;
}

std::optional<NodePair> PickNodes(const std::vector<VideoNode>& nodes, const std::string& name) {
  std::vector<VideoNode> sorted = nodes;
  // /dev/video2 before /dev/video10.
  std::sort(sorted.begin(), sorted.end(), [](const VideoNode& a, const VideoNode& b) {
    return a.path.size() != b.path.size() ? a.path.size() < b.path.size() : a.path < b.path;
  });
  NodePair pair;
  for (const VideoNode& node : sorted) {
    if (node.card.find(name) == std::string::npos) continue;
    const auto offers = [&](std::uint32_t format) {
      return std::find(node.formats.begin(), node.formats.end(), format) != node.formats.end();
    };
    if (offers(kZ16)) {
      if (pair.depth.empty()) pair.depth = node.path;
    } else if (offers(kYuyv) && pair.color.empty()) {
      pair.color = node.path;
    }
  }
  if (pair.depth.empty()) return std::nullopt;
  return pair;
}

}  // namespace corridor::drivers::realsense
