// The camera's gaze, for a camera on a pan servo (nav/policy/gaze.h): rate_hz times a second it reads the robot's
// pose, the mission's path, what the tracker follows and the odometry's speed, decides where the camera should look
// and sends it to the servo (camera/pan_target, which the driver bridge hands to it).
#pragma once

#include "nav/policy/gaze.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class GazeNode final : public PeriodicNode {
 public:
  // `options`' pan range is the servo's. Throws std::invalid_argument for bad options.
  GazeNode(Executor& executor, Bus& bus, double rate_hz, const nav::GazeOptions& options);

 private:
  void Tick() override;

  nav::GazeOptions options_;
  Topic<StampedPose>& pose_topic_ = bus().Get(topics::kPose);
  Topic<MissionState>& mission_topic_ = bus().Get(topics::kMission);
  Topic<TrackedObjects>& tracked_topic_ = bus().Get(topics::kTrackedObjects);
  Topic<drivers::WheelOdometry>& odometry_topic_ = bus().Get(topics::kOdometry);
  Topic<double>& target_topic_ = bus().Get(topics::kCameraPanTarget);
};

}  // namespace corridor::server
