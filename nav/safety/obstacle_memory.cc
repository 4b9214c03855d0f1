#include "nav/safety/obstacle_memory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace corridor::nav {
void ObstacleMemory::Update(const Pose2& robot, const std::vector<LaneResult>& lanes, double dt_s) {
  const ObstacleMemoryOptions& o = options_;
  for (Point& p : points_) p.age_s += std::max(0.0, dt_s);
  std::erase_if(points_, [&](const Point& p) {
    return p.age_s > o.keep_s || (p.world - robot.translation()).norm() > o.keep_radius_m;
  });
  // Free floor seen past a remembered point clears it.
  const Pose2 robot_inverse = robot.Inverse();
  std::erase_if(points_, [&](const Point& p) {
    const Eigen::Vector2d local = robot_inverse.Transform(p.world);
    if (local.x() < o.clear_from_m) return false;
    return std::any_of(lanes.begin(), lanes.end(), [&](const LaneResult& lane) {
      return !lane.blind && std::abs(local.y() - lane.offset_m) <= o.lane_half_width_m &&
             local.x() < lane.free_distance_m - o.cell_m;
    });
  });
  for (const LaneResult& lane : lanes) {
    if (!lane.dead_end || lane.blind) continue;
    const Eigen::Vector2d world = robot.Transform(Eigen::Vector2d(lane.point.x(), lane.point.y()));
    if ((world - robot.translation()).norm() > o.keep_radius_m) continue;
    const auto near = std::find_if(points_.begin(), points_.end(),
                                   [&](const Point& p) { return (p.world - world).norm() < o.cell_m; });
    if (near != points_.end()) {
      *near = {world, 0.0};
    } else {
      points_.push_back({world, 0.0});
    }
  }
}

void ObstacleMemory::Forget(const Eigen::Vector2d& centre, double radius_m) {
  std::erase_if(points_, [&](const Point& p) { return (p.world - centre).norm() <= radius_m; });
}

bool ObstacleMemory::Blocks(const Pose2& robot, const Twist2& command) const {
  const ObstacleMemoryOptions& o = options_;
  const double clearance = o.robot_radius_m + o.margin_m;
  double now = std::numeric_limits<double>::infinity();
  for (const Point& p : points_) now = std::min(now, (p.world - robot.translation()).norm());
  for (double t = o.sweep_step_s; t <= o.horizon_s + 1e-9; t += o.sweep_step_s) {
    const Eigen::Vector2d at = DriveArc(robot, command, t).translation();
    for (const Point& p : points_) {
      const double d = (p.world - at).norm();
      // Inside the clearance and closing in: blocked. Already inside and moving away is how the robot gets out.
      if (d < clearance && d < now - 1e-6) return true;
    }
  }
  return false;
}

Twist2 ObstacleMemory::Guard(const Pose2& robot, const Twist2& command) const {
  if (points_.empty() || !Blocks(robot, command)) return command;
  // Keeping the speed matters more than keeping the turn: a robot that bends away keeps going.
  const auto cost = [&](const Twist2& t) {
    return 2.0 * std::abs(t.linear_mps - command.linear_mps) + std::abs(t.angular_rps - command.angular_rps);
  };
  const double w_max = options_.max_turn_rps;
  std::optional<Twist2> best;
  for (const double v : {command.linear_mps, 0.5 * command.linear_mps}) {
    if (v <= 0.0) continue;
    for (const double dw : {0.0, 0.25, -0.25, 0.5, -0.5, 0.75, -0.75, 1.0, -1.0, 1.5, -1.5, 2.0, -2.0}) {
      const Twist2 candidate{v, std::clamp(command.angular_rps + dw, -w_max, w_max)};
      if ((!best || cost(candidate) < cost(*best)) && !Blocks(robot, candidate)) best = candidate;
    }
  }
  if (best) return *best;
  const Pose2 robot_inverse = robot.Inverse();
  const auto nearest = std::min_element(points_.begin(), points_.end(), [&](const Point& a, const Point& b) {
    return (a.world - robot.translation()).squaredNorm() < (b.world - robot.translation()).squaredNorm();
  });
  const double side = robot_inverse.Transform(nearest->world).y();
  return {0.0, side > 0.0 ? -0.7 * w_max : 0.7 * w_max};
}

}  // namespace corridor::nav
