// An Intel RealSense D4xx through the kernel's V4L2 nodes (no librealsense: Debian has none): the driver's thread
// finds the camera's depth node (Z16) and colour node (YUYV) by its name among /dev/video* (or takes them from the
// configuration), streams both at the configured size and rate, and hands on each depth frame, in millimetres by the
// device's depth unit, with the newest colour frame scaled to its size (the D4xx's colour is not registered to its
// depth: the colour is for people and the console, the depth for everything geometric). The intrinsics come from the
// configuration (a calibration, or the depth's fields of view): V4L2 does not carry the device's calibration. A node
// that fails (the camera unplugged) or frames that stop for silence_s: the nodes are opened anew every reconnect_s.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "drivers/depth_camera.h"
#include "drivers/realsense/realsense_options.h"
#include "drivers/serial/linked_device.h"

namespace corridor::drivers::realsense {

struct RealSenseStatus : LinkStatus {
  std::uint64_t frames = 0;  // depth frames handed on
  std::string depth_node;    // the nodes in use
  std::string color_node;
};

class RealSenseCamera final : public DepthCamera, public LinkedDevice<RealSenseStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the frames and must outlive it. Throws std::invalid_argument for
  // options that cannot work (no size, rate or depth unit, no intrinsics).
  RealSenseCamera(const RealSenseOptions& options, const Clock& clock);
  ~RealSenseCamera() override;

  CameraInfo info() const override { return info_; }
  void SetFrameHandler(FrameHandler handler) override;

 private:
  void Run(std::stop_token stop);
  void Session(std::stop_token stop);

  const RealSenseOptions options_;
  const Clock& clock_;
  CameraInfo info_;
  FrameHandler handler_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::realsense
