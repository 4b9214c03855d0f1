// The RGB-D camera interface. Implementations: the simulator (drivers/sim), real devices, test fakes.
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "drivers/clock.h"
#include "nav/geometry/camera_model.h"

namespace corridor::drivers {

struct CameraInfo {
  // Intrinsics, and the pose of the optical frame (x right, y down, z forward) in the robot base frame (x forward,
  // z up, on the floor): what the navigation algorithms use.
  nav::PinholeCamera camera;
  double min_range_m = 0.0;
  double max_range_m = 0.0;
};

// One synchronised depth + colour capture. Depth is CV_16UC1 in millimetres along the optical axis, 0 where the
// camera has no measurement; colour is CV_8UC3 BGR of the same size. Frames are immutable once published.
struct RgbdFrame {
  TimeNs stamp_ns = 0;     // capture time on the camera's clock (simulated or device)
  TimeNs arrival_ns = -1;  // when it reached the host, on the host's clock: latencies are measured from here
  std::uint64_t sequence = 0;
  cv::Mat depth_mm;
  cv::Mat color_bgr;
  // Where the camera was in the base frame when it took the frame, when it moves on the robot (a pan servo: set as
  // the frame is handed to the graph, server/nodes/driver_bridge.h); none: where CameraInfo says it is mounted.
  std::optional<Eigen::Isometry3d> base_T_camera;
};

// The camera that took `frame` (`camera` as mounted), at the pose it had then.
inline nav::PinholeCamera CameraAt(const RgbdFrame& frame, const nav::PinholeCamera& camera) {
  return frame.base_T_camera ? nav::AtPose(camera, *frame.base_T_camera) : camera;
}

class DepthCamera {
 public:
  // The handler owns the frame until it publishes it (it stamps arrival_ns).
  using FrameHandler = std::function<void(std::shared_ptr<RgbdFrame>)>;

  DepthCamera() = default;
  DepthCamera(const DepthCamera&) = delete;
  DepthCamera& operator=(const DepthCamera&) = delete;
  virtual ~DepthCamera() = default;

  virtual CameraInfo info() const = 0;
  // Installs the handler that receives every frame, called on the driver's own thread: it must return quickly
  // (hand the frame to an executor). Set it before frames start flowing; not thread-safe against delivery.
  virtual void SetFrameHandler(FrameHandler handler) = 0;
};

}  // namespace corridor::drivers
