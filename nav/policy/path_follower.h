// Follows a planned path to its goal pose: toward a look-ahead point on the path with the polar pose controller,
// then the final approach to the goal pose with the same controller (reversing allowed), then turning in place to
// the goal heading. Speeds respect the robot's limits, the path's speed zones and a mission limit, and slow to
// a stop at the goal.
#pragma once

#include <vector>

#include "nav/planner/planner.h"
#include "nav/policy/polar_controller.h"

namespace corridor::nav {

struct FollowerOptions {
  PolarGains gains;
  double lookahead_m = 0.6;  // how far ahead on the path the robot steers to
  double approach_m = 0.6;   // within this of the goal: final approach to the goal pose
  double max_linear_mps = 0.5;
  double max_angular_rps = 1.5;
  double max_linear_accel_mps2 = 0.8;  // for slowing down in time at the goal
  double position_tolerance_m = 0.01;  // done within this distance...
  double yaw_tolerance_rad = 0.0175;   // ...and this heading error (1 degree)
  double turn_in_place_rad = 1.2;      // heading error beyond which the robot turns before driving
};

struct FollowStep {
  Twist2 twist;
  bool done = false;
  double remaining_m = 0.0;                          // along the path to the goal
  double off_path_m = 0.0;                           // from the robot to the nearest point of the path
  bool final_approach = false;                       // steering to the goal pose itself (or turning to its heading)
  Eigen::Vector2d target = Eigen::Vector2d::Zero();  // where the robot steers: the look-ahead point or the goal
  double speed_limit_mps = 0.0;  // the lowest of the robot's, the mission's, the zone's and the goal's limits
};

class PathFollower {
 public:
  explicit PathFollower(const FollowerOptions& options);  // throws std::invalid_argument for bad gains

  // A new path; the last waypoint is the goal pose.
  void SetPath(std::vector<Waypoint> path);
  const std::vector<Waypoint>& path() const { return path_; }
  bool has_path() const { return !path_.empty(); }
  void Clear() { path_.clear(); }
  // Takes the robot's position as the goal's (it cannot get nearer): from the next update on it only turns to the
  // goal heading. Undone, like a reached position, when the robot is pushed away.
  void AcceptPosition() { final_turn_ = true; }

  // One control step from the robot's pose; speed_limit_mps caps the whole mission (+infinity for none).
  FollowStep Update(const Pose2& robot, double speed_limit_mps);

 private:
  // The distance along the path of the robot's projection, searched forward from the last one, and the distance
  // to it.
  double Project(const Eigen::Vector2d& p, double* distance);
  Eigen::Vector2d PointAt(double s, std::size_t* segment) const;

  FollowerOptions options_;
  std::vector<Waypoint> path_;
  std::vector<double> cumulative_;  // path length at each waypoint
  std::size_t segment_ = 0;
  bool final_turn_ = false;
};

}  // namespace corridor::nav
