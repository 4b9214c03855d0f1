#include "server/nodes/localization_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {

LocalizationNode::LocalizationNode(Executor& executor, Bus& bus, nav::Pose2 initial_pose, bool sim_truth)
    : Node("localization", executor, bus), map_T_odom_(initial_pose), sim_truth_(sim_truth) {}

void LocalizationNode::Activate() {
  auto& pose = bus().Get(topics::kPose);
  // The configured initial pose is known before the first odometry arrives.
  pose.Publish(StampedPose{clock().Now(), map_T_odom_});
  if (sim_truth_) {
    Subscribe(topics::kSimTruePose, "truth", [&pose](const auto& truth) { pose.Publish(truth); });
    SetHealth(Health::kOk, "the simulator's ground truth");
    return;
  }
  Subscribe(topics::kOdometry, "odometry", [this, &pose](const auto& odometry) {
    pose.Publish(StampedPose{odometry->stamp_ns, map_T_odom_ * odometry->odom_T_base});
  });
  SetHealth(Health::kOk, "dead reckoning from wheel odometry");
}

}  // namespace corridor::server
