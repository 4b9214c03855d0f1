#include "server/nodes/multi_view_node.h"

namespace corridor::server {

// A frame more than this from the nearest odometry reading cannot be placed: it is not filtered but dropped (the
// depth-silence watch then stops the robot if it lasts).
constexpr drivers::TimeNs kMaxOdometryGapNs = 200'000'000;

MultiViewNode::MultiViewNode(Executor& control, Bus& bus, const nav::PinholeCamera& camera,
                             const nav::MultiViewOptions& options)
    : Node("multi_view", control, bus), filter_(camera, options) {}

void MultiViewNode::Activate() {
  bus().Get(topics::kOdometry).Tap([odometry = odometry_](const drivers::WheelOdometry& o) {
    odometry->Add(o.stamp_ns, o.odom_T_base);
  });
  Subscribe(topics::kRgbdRaw, "frame", [this](const auto& frame) { OnFrame(*frame); });
  SetHealth(Health::kOk, "");
}

void MultiViewNode::OnFrame(const drivers::RgbdFrame& raw) {
  const std::optional<nav::Pose2> pose = odometry_->At(raw.stamp_ns, kMaxOdometryGapNs);
  if (!pose) {
    SetHealth(Health::kDegraded, "no odometry at a frame's time: frames are not placed, and dropped");
    return;
  }
  auto frame = std::make_shared<drivers::RgbdFrame>(raw);
  frame->depth_mm = raw.depth_mm.clone();  // the raw frame is published, and so immutable
  filter_.Apply(frame->depth_mm, *pose, frame->base_T_camera);
  SetHealth(Health::kOk, "");
  rgbd_topic_.Publish(std::move(frame));
}

}  // namespace corridor::server
