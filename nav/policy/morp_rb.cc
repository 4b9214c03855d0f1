#include "nav/policy/morp_rb.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace corridor::nav {

const char* ToString(MorpRbMode mode) {
  switch (mode) {
    case MorpRbMode::kFollow: return "follow";
    case MorpRbMode::kChangeLaneLeft: return "change_lane_left";
    case MorpRbMode::kChangeLaneRight: return "change_lane_right";
    case MorpRbMode::kStopAndTurn: return "stop_and_turn";
    case MorpRbMode::kOvertake: return "overtake";
  }
  return "unknown";
}

MorpRbDecision MorpRb::Decide(const std::vector<LaneResult>& lanes, double heading_error_rad, double dt_s) {
  const MorpRbOptions& o = options_;
  MorpRbDecision out;
  // Distance driven since the last decision, at the speed then commanded.
  overtake_left_m_ = std::max(0.0, overtake_left_m_ - last_speed_mps_ * std::max(0.0, dt_s));
  if (lanes.empty()) {
    out.mode = MorpRbMode::kStopAndTurn;
    last_speed_mps_ = 0.0;
    return out;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double nearest = kInf;
  double left = kInf;  // the nearest dead-end among the left lanes
  double right = kInf;
  for (const LaneResult& lane : lanes) {
    const double d = lane.dead_end ? lane.free_distance_m : kInf;
    nearest = std::min(nearest, d);
    if (lane.offset_m > 0.0) left = std::min(left, d);
    if (lane.offset_m < 0.0) right = std::min(right, d);
  }
  out.nearest_m = nearest;
  const double error = WrapAngle(heading_error_rad);
  const double v_safe = std::min(o.max_linear_mps, SpeedForFreeDistance(nearest - o.front_offset_m, o.stopping));

  if (nearest >= o.clear_distance_m) {
    if (side_ != 0) {
      // Just cleared an obstacle: overtake, straight on, before turning back toward the waypoint.
      side_ = 0;
      overtake_left_m_ = o.overtake_distance_m;
    }
    if (overtake_left_m_ > 0.0) {
      out.mode = MorpRbMode::kOvertake;
      out.twist = {v_safe, 0.0};
    } else {
      // The way ahead is clear: steer toward the waypoint, slowing in turns and turning in place when far off.
      out.mode = MorpRbMode::kFollow;
      out.twist.angular_rps = std::clamp(o.heading_gain * error, -o.max_angular_rps, o.max_angular_rps);
      out.twist.linear_mps = std::abs(error) > o.turn_in_place_rad ? 0.0 : v_safe * std::cos(error);
    }
    last_speed_mps_ = out.twist.linear_mps;
    return out;
  }
  // Blocked: keep the side already chosen; otherwise the freer side, or, when both are about as free, the
  // waypoint's side.
  if (side_ == 0) {
    const bool go_left = std::abs(left - right) <= o.tie_margin_m ? error >= 0.0 : left > right;
    side_ = go_left ? 1 : -1;
  }
  overtake_left_m_ = 0.0;
  const double turn = side_ * o.avoid_turn_rps;
  if (nearest < o.pass_distance_m) {
    out.mode = MorpRbMode::kStopAndTurn;
    out.twist = {0.0, turn};
  } else {
    // Slow in proportion to how near the obstacle is, like a car changing lane behind a slower one.
    out.mode = side_ > 0 ? MorpRbMode::kChangeLaneLeft : MorpRbMode::kChangeLaneRight;
    const double slow = (nearest - o.pass_distance_m) / (o.clear_distance_m - o.pass_distance_m);
    out.twist = {v_safe * std::clamp(slow, 0.2, 1.0), turn};
  }
  last_speed_mps_ = out.twist.linear_mps;
  return out;
}

}  // namespace corridor::nav
