#include "server/nodes/localization_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {

LocalizationNode::LocalizationNode(Executor& executor, Bus& bus, nav::Pose2 initial_pose)
    : Node("localization", executor, bus), map_T_odom_(initial_pose) {}

void LocalizationNode::Activate() {
  auto& pose = bus().Get(topics::kPose);
  // The configured initial pose is known before the first odometry arrives.
  pose.Publish(StampedPose{clock().Now(), map_T_odom_});
  Subscribe(topics::kOdometry, "odometry", [this, &pose](const auto& odometry) {
    pose.Publish(StampedPose{odometry->stamp_ns, map_T_odom_ * odometry->odom_T_base});
  });
  SetHealth(Health::kOk, "dead reckoning from wheel odometry");
}

}  // namespace corridor::server
