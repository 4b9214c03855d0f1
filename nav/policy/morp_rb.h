// MORP-RB, the rule-based local policy of DPoom (Kim et al., IEEE Access 2022, section III-E) on MORP's lanes: drive
// toward the global path's next waypoint while the lanes ahead are free; when they are not, change lane like a car,
// steering to the side with more free distance and slowing down; when something is too close to pass, stop and turn
// toward the freer side. Speeds are further capped by what the robot can stop within (nav/safety/stopping.h).
//
// Like a driver, it commits: once it has chosen a side it keeps it while blocked, and when the lanes clear it drives
// on straight (overtaking) for overtake_distance_m before turning back toward the waypoint. Without that memory the
// robot turns away from an obstacle until the lanes clear, then back toward the goal and the obstacle, and stalls.
#pragma once

#include <string>
#include <vector>

#include "nav/geometry/pose2.h"
#include "nav/ground/morp.h"
#include "nav/safety/stopping.h"

namespace corridor::nav {

struct MorpRbOptions {
  double max_linear_mps = 0.26;  // DPoom's top speed
  double max_angular_rps = 1.0;
  double clear_distance_m = 1.0;     // lanes free at least this far: follow the path
  double pass_distance_m = 0.45;     // nearer than this the robot cannot steer around: stop and turn
  double heading_gain = 1.5;         // turn rate per radian of heading error while following
  double avoid_turn_rps = 0.7;       // turn rate while changing lane
  double turn_in_place_rad = 1.0;    // heading error beyond which the robot turns before driving
  double tie_margin_m = 0.15;        // sides this close in free distance count as equal: turn toward the goal
  double overtake_distance_m = 0.9;  // straight on after the lanes clear, before turning back to the waypoint
  double front_offset_m = 0.2;       // from the base's centre (where lane distances start) to its front
  StoppingModel stopping;
};

enum class MorpRbMode { kFollow, kChangeLaneLeft, kChangeLaneRight, kStopAndTurn, kOvertake };
const char* ToString(MorpRbMode mode);

struct MorpRbDecision {
  Twist2 twist;
  MorpRbMode mode = MorpRbMode::kFollow;
  double nearest_m = 0.0;  // the nearest dead-end ahead over all lanes
};

class MorpRb {
 public:
  explicit MorpRb(const MorpRbOptions& options) : options_(options) {}

  // One decision from this frame's lanes (left lanes have offset > 0), the heading error to the next waypoint
  // (radians, positive: the waypoint is to the left) and the time since the previous decision. An empty lane list
  // means no sight: stop.
  MorpRbDecision Decide(const std::vector<LaneResult>& lanes, double heading_error_rad, double dt_s);

 private:
  MorpRbOptions options_;
  int side_ = 0;  // +1 left, -1 right, 0 none: the side chosen around the current obstacle
  double overtake_left_m_ = 0.0;
  double last_speed_mps_ = 0.0;
};

}  // namespace corridor::nav
