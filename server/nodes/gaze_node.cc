#include "server/nodes/gaze_node.h"

#include <cmath>
#include <numbers>
#include <string>

#include <spdlog/fmt/fmt.h>

namespace corridor::server {

GazeNode::GazeNode(Executor& executor, Bus& bus, double rate_hz, const nav::GazeOptions& options)
    : PeriodicNode("gaze", executor, bus, rate_hz), options_(options) {
  nav::ValidateGazeOptions(options);
}

void GazeNode::Tick() {
  const auto pose = pose_topic_.latest();
  if (!pose) {
    SetHealth(Health::kDegraded, "no pose yet: looking straight ahead");
    target_topic_.Publish(0.0);
    return;
  }
  nav::GazeInput input;
  input.map_T_base = pose->pose;
  if (const auto mission = mission_topic_.latest(); mission && mission->status == nav::MissionStatus::kActive) {
    for (const nav::Pose2& p : mission->path) input.path.push_back(p.translation());
  }
  if (const auto tracked = tracked_topic_.latest()) {
    for (const nav::TrackedObject& o : tracked->surroundings.objects) input.obstacles.push_back(o.position);
  }
  if (const auto odometry = odometry_topic_.latest()) input.speed_mps = odometry->velocity.linear_mps;
  const nav::GazeDecision d = nav::DecideGaze(input, options_);
  target_topic_.Publish(d.pan_rad);
  SetHealth(Health::kOk,
            fmt::format("looking {} ({:.0f} degrees)", nav::ToString(d.reason), d.pan_rad * 180.0 / std::numbers::pi));
}

}  // namespace corridor::server
