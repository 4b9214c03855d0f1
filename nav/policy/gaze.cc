#include "nav/policy/gaze.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {
namespace {

// The distance from `p` to the segment a-b.
double ToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// The path from the robot on: the robot's position, then the waypoints after the segment nearest to it.
std::vector<Eigen::Vector2d> PathAhead(const std::vector<Eigen::Vector2d>& path, const Eigen::Vector2d& robot) {
  std::size_t nearest = 0;  // the segment (nearest, nearest + 1), or the only waypoint
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double d = ToSegment(robot, path[i], path[i + 1]);
    if (d < best) {
      best = d;
      nearest = i;
    }
  }
  std::vector<Eigen::Vector2d> ahead{robot};
  ahead.insert(ahead.end(), path.begin() + static_cast<std::ptrdiff_t>(std::min(nearest + 1, path.size() - 1)),
               path.end());
  return ahead;
}

// The point `distance_m` along a polyline (its end when shorter).
Eigen::Vector2d Along(const std::vector<Eigen::Vector2d>& line, double distance_m) {
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const double length = (line[i + 1] - line[i]).norm();
    if (distance_m <= length && length > 0.0) return line[i] + (line[i + 1] - line[i]) * (distance_m / length);
    distance_m -= length;
  }
  return line.back();
}

}  // namespace

void ValidateGazeOptions(const GazeOptions& o) {
  if (!(o.lookahead_m > 0.0)) throw std::invalid_argument("gaze.lookahead_m must be positive");
  if (!(o.obstacle_min_m >= 0.0) || !(o.obstacle_max_m > o.obstacle_min_m)) {
    throw std::invalid_argument("gaze.obstacle_max_m must be above obstacle_min_m (>= 0)");
  }
  if (!(o.path_margin_m > 0.0) || !(o.goal_near_m >= 0.0) || !(o.moving_mps >= 0.0)) {
    throw std::invalid_argument("gaze: path_margin_m must be positive, goal_near_m and moving_mps not negative");
  }
  if (!(o.keep_ahead_deg >= 0.0 && o.keep_ahead_deg <= 180.0)) {
    throw std::invalid_argument("gaze.keep_ahead_deg must be within 0-180");
  }
  if (!(o.min_pan_rad <= 0.0 && o.max_pan_rad >= 0.0)) throw std::invalid_argument("gaze: the pan range must hold 0");
}

const char* ToString(GazeReason reason) {
  switch (reason) {
    case GazeReason::kAhead: return "ahead";
    case GazeReason::kPath: return "path";
    case GazeReason::kObstacle: return "obstacle";
    case GazeReason::kBackward: return "backward";
  }
  return "unknown";
}

GazeDecision DecideGaze(const GazeInput& input, const GazeOptions& options) {
  GazeDecision out;
  const Eigen::Vector2d robot = input.map_T_base.translation();
  const Pose2 base_T_map = input.map_T_base.Inverse();
  const auto bearing = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d local = base_T_map.Transform(p);
    return std::atan2(local.y(), local.x());
  };
  const bool moving = std::abs(input.speed_mps) > options.moving_mps;
  bool following = false;
  if (!input.path.empty()) {
    const std::vector<Eigen::Vector2d> ahead = PathAhead(input.path, robot);
    if (!moving && options.goal_near_m > 0.0 && (input.path.back() - robot).norm() <= options.goal_near_m) {
      out.reason = GazeReason::kBackward;
      out.pan_rad = std::abs(options.min_pan_rad) > options.max_pan_rad ? options.min_pan_rad : options.max_pan_rad;
    } else {
      following = true;
      // The nearest obstacle in the band that the path ahead passes.
      double nearest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector2d& o : input.obstacles) {
        const double d = (o - robot).norm();
        if (d < options.obstacle_min_m || d > options.obstacle_max_m || d >= nearest) continue;
        bool on_path = false;
        for (std::size_t i = 0; i + 1 < ahead.size() && !on_path; ++i) {
          on_path = ToSegment(o, ahead[i], ahead[i + 1]) <= options.path_margin_m;
        }
        if (!on_path) continue;
        nearest = d;
        out.looked_at = o;
      }
      if (out.looked_at) {
        out.reason = GazeReason::kObstacle;
      } else if (ahead.size() >= 2) {
        out.reason = GazeReason::kPath;
        out.looked_at = Along(ahead, options.lookahead_m);
      }
      if (out.looked_at && (*out.looked_at - robot).norm() > 1e-3) out.pan_rad = bearing(*out.looked_at);
    }
  }
  if (following) {
    const double keep = options.keep_ahead_deg * std::numbers::pi / 180.0;
    out.pan_rad = std::clamp(out.pan_rad, -keep, keep);
  }
  out.pan_rad = std::clamp(out.pan_rad, options.min_pan_rad, options.max_pan_rad);
  return out;
}

}  // namespace corridor::nav
