// A V4L2 video node streaming into memory-mapped buffers (the kernel's video capture API, <linux/videodev2.h>): the
// format and rate set, buffers queued, and each filled buffer lent out until the next one is asked for. Also the list
// of the machine's video nodes with their names and formats (what the console's Devices page and the RealSense
// driver's search read).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "drivers/clock.h"
#include "drivers/realsense/v4l2_frames.h"

namespace corridor::drivers::realsense {

// Every /dev/video* that answers VIDIOC_QUERYCAP as a capture device, with the formats it offers (none on a machine
// without cameras).
std::vector<VideoNode> ListVideoNodes();

class V4l2Capture {
 public:
  // Opens `path`, asks for `format` at width x height and fps, maps buffers and starts streaming. Throws
  // std::runtime_error when the node cannot (no such node, busy, the format refused).
  V4l2Capture(const std::string& path, std::uint32_t format, int width, int height, int fps);
  ~V4l2Capture();  // stops streaming, unmaps, closes
  V4l2Capture(const V4l2Capture&) = delete;
  V4l2Capture& operator=(const V4l2Capture&) = delete;

  int fd() const { return fd_; }
  int width() const { return width_; }  // as the driver set them (it may round the size asked for)
  int height() const { return height_; }
  int stride() const { return stride_; }

  struct Buffer {
    std::span<const std::uint8_t> bytes;
    TimeNs stamp_ns = 0;  // the driver's time stamp (CLOCK_MONOTONIC)
    std::uint32_t sequence = 0;
  };
  // The next filled buffer, waiting up to timeout_s: none when none came. Valid until the next call (the one before
  // is handed back to the driver then). Throws std::runtime_error when the node fails (the camera unplugged).
  std::optional<Buffer> Next(double timeout_s);

 private:
  void Requeue();

  int fd_ = -1;
  int width_ = 0, height_ = 0, stride_ = 0;
  std::vector<std::span<std::uint8_t>> buffers_;
  int lent_ = -1;  // the buffer lent out by Next, handed back at the next call
};

}  // namespace corridor::drivers::realsense
