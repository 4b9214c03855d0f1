// What the stereo camera's driver does with V4L2's buffers that needs no device: a buffer (MJPEG or YUYV) decoded to a
// BGR image, a side-by-side frame split into its two views, and two separate cameras' frames paired by their time
// stamps. Tested on recorded buffers (opencv-doc's real pairs written as a side-by-side camera would send them).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "drivers/clock.h"
#include "drivers/realsense/v4l2_frames.h"

namespace corridor::drivers::stereo {

// The formats cheap UVC stereo cameras send: MJPEG (a JPEG a frame; the full rate at high resolutions) or YUYV.
enum class VideoFormat { kMjpeg, kYuyv };
inline constexpr std::uint32_t kMjpg = realsense::FourCc('M', 'J', 'P', 'G');
std::uint32_t FourCcOf(VideoFormat format);

// One buffer as a BGR image of width x height (`stride`: YUYV's bytes a row). std::invalid_argument for a buffer that
// is not one: a JPEG that does not decode (USB cameras send torn frames when the bus is busy), a decoded image of
// another size, a YUYV buffer too short.
cv::Mat DecodeBuffer(std::span<const std::uint8_t> bytes, VideoFormat format, int width, int height, int stride);

// The node of a side-by-side camera: the lowest-numbered video node of a device whose name contains `name` that
// offers `format`; none when there is none.
std::optional<std::string> PickStereoNode(const std::vector<realsense::VideoNode>& nodes, const std::string& name,
                                          VideoFormat format);

// A side-by-side frame's views, the left camera's from its left half (shallow: they share the frame's pixels).
// std::invalid_argument for an odd width.
void SplitSideBySide(const cv::Mat& frame, cv::Mat& left, cv::Mat& right);

// Cameras that are not synchronised (two of a pair, a pair and a third): each camera's newest frame, and a set of
// them whenever all are at most `tolerance_ns` apart. A frame is used in one set only.
class FrameSet {
 public:
  // `cameras`: 2 or more (std::invalid_argument otherwise).
  FrameSet(int cameras, TimeNs tolerance_ns);

  // Camera `camera`'s (from 0) newest frame.
  void Push(int camera, TimeNs stamp_ns, cv::Mat image);

  struct Set {
    TimeNs stamp_ns = 0;          // the oldest of them
    std::vector<cv::Mat> images;  // one a camera, in the cameras' order
  };
  // The set of the newest frames when they are close enough in time; none otherwise.
  std::optional<Set> Take();

 private:
  struct Frame {
    TimeNs stamp_ns = 0;
    cv::Mat image;
  };
  TimeNs tolerance_ns_;
  std::vector<std::optional<Frame>> newest_;
};

}  // namespace corridor::drivers::stereo
