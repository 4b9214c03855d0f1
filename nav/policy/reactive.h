// The comparison policy for the scenario runner: a simple memoryless reactive controller on obstacle points (the
// voxel front end's output), as the point-cloud pipelines MORP is measured against use. It drives toward the
// waypoint while a corridor of the robot's width ahead is clear, steers away from the nearer side and slows when
// something is in it, and stops and turns when it is too close. No lane commitment, no overtaking.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/safety/stopping.h"

namespace corridor::nav {

struct ReactiveOptions {
  double max_linear_mps = 0.26;
  double max_angular_rps = 1.0;
  double half_width_m = 0.25;  // the corridor checked ahead: the robot's radius and a margin
  double clear_distance_m = 1.0;
  double stop_distance_m = 0.45;
  double heading_gain = 1.5;
  double avoid_turn_rps = 0.7;
  double turn_in_place_rad = 1.0;
  double front_offset_m = 0.2;
  StoppingModel stopping;
};

// One command from obstacle points (base frame, x forward, y left) and the heading error to the waypoint.
Twist2 ReactiveCommand(const std::vector<Eigen::Vector2f>& obstacles, double heading_error_rad,
                       const ReactiveOptions& options);

}  // namespace corridor::nav
