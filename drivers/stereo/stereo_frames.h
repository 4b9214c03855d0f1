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

// Two cameras that are not synchronised: each side's newest frame, and a pair whenever the two are at most
// `tolerance_ns` apart. A frame is used in one pair only.
class FramePairer {
 public:
  explicit FramePairer(TimeNs tolerance_ns) : tolerance_ns_(tolerance_ns) {}

  void PushLeft(TimeNs stamp_ns, cv::Mat image) { left_ = Frame{stamp_ns, std::move(image)}; }
  void PushRight(TimeNs stamp_ns, cv::Mat image) { right_ = Frame{stamp_ns, std::move(image)}; }

  struct Pair {
    TimeNs stamp_ns = 0;  // the older of the two
    cv::Mat left, right;
  };
  // The pair of the newest frames when they are close enough in time; none otherwise.
  std::optional<Pair> Take();

 private:
  struct Frame {
    TimeNs stamp_ns = 0;
    cv::Mat image;
  };
  TimeNs tolerance_ns_;
  std::optional<Frame> left_, right_;
};

}  // namespace corridor::drivers::stereo
