#include "nav/policy/path_follower.h"

#include <algorithm>
#include <cmath>

namespace corridor::nav {

PathFollower::PathFollower(const FollowerOptions& options) : options_(options) { ValidateGains(options.gains); }

void PathFollower::SetPath(std::vector<Waypoint> path) {
  path_ = std::move(path);
  cumulative_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i) {
    cumulative_[i] = cumulative_[i - 1] + (path_[i].pose.translation() - path_[i - 1].pose.translation()).norm();
  }
  segment_ = 0;
  final_turn_ = false;
}

double PathFollower::Project(const Eigen::Vector2d& p, double* distance) {
  double best_distance = std::numeric_limits<double>::infinity();
  double best_s = cumulative_[segment_];
  std::size_t best_segment = segment_;
  // Look a few segments ahead only: the robot progresses along the path, it does not jump.
  for (std::size_t i = segment_; i + 1 < path_.size() && i < segment_ + 4; ++i) {
    const Eigen::Vector2d a = path_[i].pose.translation();
    const Eigen::Vector2d ab = path_[i + 1].pose.translation() - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d = (a + t * ab - p).norm();
    if (d < best_distance) {
      best_distance = d;
      best_s = cumulative_[i] + t * std::sqrt(len2);
      best_segment = i;
    }
  }
  segment_ = best_segment;
  *distance = best_distance;
  return best_s;
}

Eigen::Vector2d PathFollower::PointAt(double s, std::size_t* segment) const {
  for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
    if (s <= cumulative_[i + 1]) {
      const double len = cumulative_[i + 1] - cumulative_[i];
      const double t = len > 0.0 ? (s - cumulative_[i]) / len : 0.0;
      *segment = i;
      return path_[i].pose.translation() + t * (path_[i + 1].pose.translation() - path_[i].pose.translation());
    }
  }
  *segment = path_.size() - 1;
  return path_.back().pose.translation();
}

FollowStep PathFollower::Update(const Pose2& robot, double speed_limit_mps) {
  FollowStep step;
  if (path_.empty()) {
    step.done = true;
    return step;
  }
  const Pose2& goal = path_.back().pose;
  const double to_goal = (goal.translation() - robot.translation()).norm();
  step.off_path_m = to_goal;
  const double s = path_.size() > 1 ? Project(robot.translation(), &step.off_path_m) : 0.0;
  step.remaining_m = std::max(to_goal, cumulative_.back() - s);
  step.target = goal.translation();

  // At the goal position the robot turns in place to the goal heading. The phase is latched: a few millimetres
  // of drift while turning must not send it back to the approach, or it would never settle.
  if (to_goal <= options_.position_tolerance_m) final_turn_ = true;
  if (final_turn_ && to_goal > 5.0 * options_.position_tolerance_m) final_turn_ = false;  // pushed away
  if (final_turn_) {
    step.final_approach = true;
    const double yaw_error = WrapAngle(goal.yaw_rad - robot.yaw_rad);
    if (std::abs(yaw_error) <= options_.yaw_tolerance_rad) {
      step.done = true;
      return step;
    }
    // At least this turn rate: below it the base would creep and never close the last fraction of a degree.
    constexpr double kMinTurnRps = 0.05;
    const double w =
        std::clamp(options_.gains.k_alpha * yaw_error, -options_.max_angular_rps, options_.max_angular_rps);
    step.twist.angular_rps = std::abs(w) < kMinTurnRps ? std::copysign(kMinTurnRps, yaw_error) : w;
    return step;
  }

  PolarCommand command;
  std::size_t segment = path_.size() - 1;
  if (to_goal <= options_.approach_m || path_.size() == 1) {
    step.final_approach = true;
    command = PolarControl(robot, goal, options_.gains, /*allow_reverse=*/true);
  } else {
    const Eigen::Vector2d carrot = PointAt(s + options_.lookahead_m, &segment);
    step.target = carrot;
    const double carrot_yaw = path_[std::min(segment, path_.size() - 2)].pose.yaw_rad;
    command = PolarControl(robot, Pose2{carrot.x(), carrot.y(), carrot_yaw}, options_.gains, false);
    // Steering to a point a look-ahead away would crawl at k_rho * lookahead: drive at the path's pace instead.
    command.twist.linear_mps = options_.max_linear_mps;
    if (std::abs(command.alpha) > options_.turn_in_place_rad) command.twist.linear_mps = 0.0;
  }

  // Speed limits: the robot's, the mission's, the speed zone of this stretch, and stopping in time at the goal.
  double v_max = std::min(options_.max_linear_mps, speed_limit_mps);
  v_max = std::min(v_max, path_[std::min(segment_ + 1, path_.size() - 1)].speed_limit_mps);
  v_max = std::min(v_max, std::sqrt(2.0 * options_.max_linear_accel_mps2 * std::max(0.0, step.remaining_m)));
  step.speed_limit_mps = v_max;
  const double v = command.twist.linear_mps;
  const double w = command.twist.angular_rps;
  // Scale both together so the robot keeps its curvature when a limit applies.
  double scale = 1.0;
  if (std::abs(v) > v_max) scale = std::min(scale, v_max / std::abs(v));
  if (std::abs(w) > options_.max_angular_rps) scale = std::min(scale, options_.max_angular_rps / std::abs(w));
  step.twist = {v * scale, w * scale};
  return step;
}

}  // namespace corridor::nav
