// Where the camera on a pan servo should look: ASNS's gaze (its section 4.9, "IGM"), as corridor reads it. The
// paper's rules name what to look at - the path just ahead, the nearest obstacle between 0.9 and 5 m, backwards
// when near the goal - not how to weigh them, so corridor chose (docs/asns.md):
//   1. near the goal (the leg's end within goal_near_m) and nearly still: backwards, as far as the servo turns (off by
//      default: goal_near_m 0, below);
//   2. else the nearest obstacle between obstacle_min_m and obstacle_max_m that stands within path_margin_m of the
//      path ahead (it is where the path must go round);
//   3. else the path's point lookahead_m ahead of the robot (it turns the camera into a bend before the robot);
//   4. with no path, straight ahead.
// Whatever it chooses while it follows a path (all but rule 1), the camera keeps within keep_ahead_deg of straight
// ahead: the local policy reads the lanes in front of the robot from the same camera, and a lane whose floor near
// the robot is out of view is blind, which stops the robot (nav/ground/morp.h). With the simulator's 85 degree camera
// and MORP's lanes a robot's width across, 15 degrees keeps the lanes the robot drives on in view from 0.6 m; a
// robot that stopped because the camera looked away would never start again. The angle goes to the servo, which
// turns at its own speed within its limits.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct GazeOptions {
  double lookahead_m = 1.5;
  double obstacle_min_m = 0.9;
  double obstacle_max_m = 5.0;
  double path_margin_m = 0.6;
  // 0: never backwards. A robot whose lanes come from the same camera is blind ahead while it looks back, and its
  // last centimetres to the goal (the polar controller's, to 1 cm) are driven: looking back stops it short of the goal.
  double goal_near_m = 0.0;
  double keep_ahead_deg = 15.0;
  double moving_mps = 0.05;
  // The servo's range (radians, counter-clockwise from straight ahead): what "backwards" becomes.
  double min_pan_rad = -2.6;
  double max_pan_rad = 2.6;
};

// Throws std::invalid_argument naming the option when `options` cannot work.
void ValidateGazeOptions(const GazeOptions& options);

enum class GazeReason { kAhead, kPath, kObstacle, kBackward };
const char* ToString(GazeReason reason);

struct GazeInput {
  Pose2 map_T_base;
  std::vector<Eigen::Vector2d> path;       // the current leg's waypoints (map frame); empty: no mission
  std::vector<Eigen::Vector2d> obstacles;  // what the tracker follows (map frame)
  double speed_mps = 0.0;                  // the robot's forward speed
};

struct GazeDecision {
  double pan_rad = 0.0;
  GazeReason reason = GazeReason::kAhead;
  std::optional<Eigen::Vector2d> looked_at;  // map frame (none for straight ahead or backwards)
};

GazeDecision DecideGaze(const GazeInput& input, const GazeOptions& options);

}  // namespace corridor::nav
