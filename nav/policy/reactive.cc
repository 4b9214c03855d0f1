#include "nav/policy/reactive.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace corridor::nav {

Twist2 ReactiveCommand(const std::vector<Eigen::Vector2f>& obstacles, double heading_error_rad,
                       const ReactiveOptions& o) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double ahead = kInf;  // nearest obstacle in the corridor
  double left = kInf;   // nearest obstacle within reach on each side, corridor included
  double right = kInf;
  for (const Eigen::Vector2f& p : obstacles) {
    if (p.x() <= 0.0f) continue;
    const double distance = std::hypot(p.x(), p.y());
    if (std::abs(p.y()) <= o.half_width_m) ahead = std::min(ahead, static_cast<double>(p.x()));
    if (std::abs(p.y()) <= o.clear_distance_m) {
      double& side = p.y() >= 0.0f ? left : right;
      side = std::min(side, distance);
    }
  }
  const double error = WrapAngle(heading_error_rad);
  const double v_safe = std::min(o.max_linear_mps, SpeedForFreeDistance(ahead - o.front_offset_m, o.stopping));
  Twist2 out;
  if (ahead >= o.clear_distance_m) {
    out.angular_rps = std::clamp(o.heading_gain * error, -o.max_angular_rps, o.max_angular_rps);
    out.linear_mps = std::abs(error) > o.turn_in_place_rad ? 0.0 : v_safe * std::cos(error);
    return out;
  }
  const double away = left < right ? -1.0 : 1.0;  // turn away from the nearer side
  out.angular_rps = away * o.avoid_turn_rps;
  if (ahead >= o.stop_distance_m) {
    const double slow = (ahead - o.stop_distance_m) / (o.clear_distance_m - o.stop_distance_m);
    out.linear_mps = v_safe * std::clamp(slow, 0.2, 1.0);
  }
  return out;
}

}  // namespace corridor::nav
