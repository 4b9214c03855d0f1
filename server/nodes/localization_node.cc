#include "server/nodes/localization_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {

LocalizationNode::LocalizationNode(Executor& executor, Bus& bus, const drivers::Clock& clock, nav::Pose2 initial_pose)
    : Node("localization", executor.name(), clock), executor_(executor), bus_(bus), map_T_odom_(initial_pose) {}

void LocalizationNode::Activate() {
  auto& pose = bus_.Get(topics::kPose);
  // The configured initial pose is known before the first odometry arrives.
  pose.Publish(StampedPose{clock().Now(), map_T_odom_});
  bus_.Get(topics::kOdometry).Subscribe(executor_, [this, &pose](const auto& odometry) {
    LoopTimer timer(stats(), clock());
    pose.Publish(StampedPose{odometry->stamp_ns, map_T_odom_ * odometry->odom_T_base});
  });
  SetHealth(Health::kOk, "dead reckoning from wheel odometry");
}

}  // namespace corridor::server
