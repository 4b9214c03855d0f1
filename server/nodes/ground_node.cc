#include "server/nodes/ground_node.h"

#include <chrono>

#include "server/runtime/topics.h"

namespace corridor::server {

GroundNode::GroundNode(Executor& control, Bus& bus, const drivers::CameraInfo& camera, const nav::MorpOptions& options,
                       nav::LocalPolicyKind policy)
    : Node("ground", control, bus), morp_(camera.camera, options),
      scan_(camera.camera, nav::ForObstacleMemory(nav::DepthScanOptions{})) {
  if (policy == nav::LocalPolicyKind::kVoxelReactive) voxels_.emplace(camera.camera, nav::VoxelObstacleOptions{});
}

GroundLanes GroundNode::Process(const drivers::RgbdFrame& frame) {
  GroundLanes out{frame.stamp_ns, frame.arrival_ns, frame.sequence, 0.0, {}, {}, {}, {}};
  if (voxels_) {
    out.obstacles = voxels_->Process(frame.depth_mm);
  } else {
    out.lanes = morp_.Process(frame.depth_mm);
    out.scan = scan_.Process(frame.depth_mm);
    out.scan_view = scan_.View(nav::Pose2{});
  }
  return out;
}

void GroundNode::Activate() {
  auto& lanes = bus().Get(topics::kGroundLanes);
  // Frames are stamped in the camera's time (simulated or device); the front end's own time is wall time from the
  // moment the control executor takes the frame up to the lanes being ready (the loop "frame" times it too).
  Subscribe(topics::kRgbd, "frame", [this, &lanes](const std::shared_ptr<const drivers::RgbdFrame>& frame) {
    const auto start = std::chrono::steady_clock::now();
    GroundLanes out = Process(*frame);
    out.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    lanes.Publish(std::move(out));
  });
  SetHealth(Health::kOk, voxels_ ? "voxel grid front end" : std::to_string(morp_.lane_count()) + " lanes");
}

}  // namespace corridor::server
