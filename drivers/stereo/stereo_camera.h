// A stereo camera through the kernel's V4L2 nodes: one side-by-side UVC device (a frame holds both views) or two UVC
// cameras (frames paired by time stamp), MJPEG or YUYV, and optionally a third UVC camera for ASNS's wide baseline
// (its frames joined by time stamp). The driver's thread streams the node(s), decodes each frame, and hands every
// pair (or three) to MultiBaselineDepth, which rectifies, matches, fuses and gives the depth frame every depth camera
// of corridor gives. The calibration comes from the configuration (corridor-stereo calibrate). A node that fails (the
// camera unplugged), or frames that stop for silence_s: the nodes are opened anew every reconnect_s; frames that do not
// decode (a torn MJPEG frame) are dropped and counted, and a camera giving only those goes stale.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "drivers/depth_camera.h"
#include "drivers/serial/linked_device.h"
#include "drivers/stereo/stereo_options.h"

namespace corridor::drivers::stereo {

struct StereoCameraStatus : LinkStatus {
  std::uint64_t frames = 0;      // depth frames handed on
  std::uint64_t bad_frames = 0;  // buffers that did not decode
  std::string nodes;             // the node(s) in use
};

class StereoCamera final : public DepthCamera, public LinkedDevice<StereoCameraStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the frames and must outlive it. Throws std::invalid_argument for
  // options that cannot work (a calibration of another size, two cameras without both nodes, bad timeouts).
  StereoCamera(const StereoCameraOptions& options, const Clock& clock);
  ~StereoCamera() override;

  CameraInfo info() const override { return depth_->info(); }
  void SetFrameHandler(FrameHandler handler) override;

 private:
  void Run(std::stop_token stop);
  void Session(std::stop_token stop);
  void Deliver(TimeNs stamp_ns, const cv::Mat& left, const cv::Mat& right, const cv::Mat& third);

  const StereoCameraOptions options_;
  const Clock& clock_;
  std::unique_ptr<MultiBaselineDepth> depth_;  // used by the driver's thread only (after construction)
  FrameHandler handler_;
  std::uint64_t sequence_ = 0;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::stereo
