#include "server/nodes/ground_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {

GroundNode::GroundNode(Executor& control, Bus& bus, const drivers::Clock& clock, const drivers::CameraInfo& camera,
                       const nav::MorpOptions& options)
    : Node("ground", control.name(), clock), executor_(control), bus_(bus), morp_(camera.camera, options),
      scan_(camera.camera, nav::ForObstacleMemory(nav::DepthScanOptions{})) {}

void GroundNode::Activate() {
  auto& lanes = bus_.Get(topics::kGroundLanes);
  // Frames are stamped in the camera's time (simulated or device), so latency is measured on this node's clock:
  // from the moment the control executor takes the frame up to the lanes being ready. The same measurement feeds
  // the node's loop statistics.
  bus_.Get(topics::kRgbd).Subscribe(executor_, [this, &lanes](const std::shared_ptr<const drivers::RgbdFrame>& frame) {
    const drivers::TimeNs start = clock().Now();
    GroundLanes out{frame->stamp_ns, frame->arrival_ns, frame->sequence, 0.0, morp_.Process(frame->depth_mm),
                    scan_.Process(frame->depth_mm), scan_.View(nav::Pose2{})};
    stats().Record(start);
    out.latency_ms = static_cast<double>(clock().Now() - start) * 1e-6;
    lanes.Publish(std::move(out));
  });
  SetHealth(Health::kOk, std::to_string(morp_.lane_count()) + " lanes");
}

}  // namespace corridor::server
