// Localization at skeleton depth: the robot's pose in the map is its wheel odometry placed at the configured
// initial pose (dead reckoning; it drifts), or, in the simulator when configured (localization.source: sim_truth), the
// simulator's ground truth. Map matching and relocalization replace this in nav/localization.
#pragma once

#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class LocalizationNode final : public Node {
 public:
  LocalizationNode(Executor& executor, Bus& bus, nav::Pose2 initial_pose, bool sim_truth = false);
  void Activate() override;

 private:
  nav::Pose2 map_T_odom_;
  bool sim_truth_;
};

}  // namespace corridor::server
