#include "nav/policy/reactive_navigator.h"

#include <cmath>
#include <vector>

namespace corridor::nav {

const char* ToString(LocalPolicyKind kind) {
  switch (kind) {
    case LocalPolicyKind::kMorpRb: return "morp-rb";
    case LocalPolicyKind::kVoxelReactive: return "voxel-reactive";
    case LocalPolicyKind::kMorpIl: return "morp-il";
    case LocalPolicyKind::kTakiguchi: return "takiguchi";
    case LocalPolicyKind::kFlmc: return "flmc";
  }
  return "unknown";
}

std::optional<LocalPolicyKind> ParseLocalPolicy(const std::string& name) {
  for (LocalPolicyKind kind : {LocalPolicyKind::kMorpRb, LocalPolicyKind::kVoxelReactive, LocalPolicyKind::kMorpIl,
                               LocalPolicyKind::kTakiguchi, LocalPolicyKind::kFlmc}) {
    if (name == ToString(kind)) return kind;
  }
  return std::nullopt;
}

ReactiveNavigator::ReactiveNavigator(const FollowerOptions& follower, const ReactiveOptions& reactive,
                                     double replan_distance_m)
    : follower_(follower), reactive_(reactive), replan_distance_m_(replan_distance_m) {}

void ReactiveNavigator::SetPath(std::vector<Waypoint> path, std::shared_ptr<const Costmap>) {
  follower_.SetPath(std::move(path));
}

LocalStep ReactiveNavigator::Update(const Pose2& robot, const FrameView& frame, double speed_limit_mps, double,
                                    const Surroundings*) {
  LocalStep out;
  const FollowStep follow = follower_.Update(robot, speed_limit_mps);
  out.remaining_m = follow.remaining_m;
  if (follow.done) {
    out.done = true;
    return out;
  }
  if (follow.off_path_m > replan_distance_m_) {
    out.replan = true;
    return out;
  }
  static const std::vector<Eigen::Vector2f> kNone;
  const std::vector<Eigen::Vector2f>& obstacles = frame.obstacles != nullptr ? *frame.obstacles : kNone;
  const Eigen::Vector2d to_target = follow.target - robot.translation();
  ReactiveOptions options = reactive_;
  options.max_linear_mps = std::min(options.max_linear_mps, follow.speed_limit_mps);
  out.twist = ReactiveCommand(obstacles, std::atan2(to_target.y(), to_target.x()) - robot.yaw_rad, options);
  out.avoiding = true;
  return out;
}

}  // namespace corridor::nav
