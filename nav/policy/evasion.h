// Stepping out of the way of people: the last check on a command before it goes out, when a laser tracks moving
// objects around the robot (nav/tracking/moving_objects.h).
//
// Each moving object is predicted at constant velocity for a horizon, the robot along the arc of a command; a
// command is in conflict when the two footprints (with a margin) come closer than that while still closing in.
// A command without conflict passes unchanged. Otherwise, as in a dynamic window (Fox, Burgard and Thrun, 1997)
// with velocity obstacles' prediction (Fiorini and Shiller, 1998), a set of manoeuvres is searched: arcs (forward,
// stopped, reversing, each bending either way) and, since a differential base cannot move sideways, turning in
// place by 45 or 90 degrees either way and then driving straight forward or back. The clear one nearest the
// command wins if there is one, else the one that puts the conflict latest and keeps the closest approach widest;
// its first twist goes out, and the search is made again on the next frame. Every candidate must also keep clear
// of what stands still (the scan's static points and the obstacle memory's) over a shorter horizon.
//
// People in the DPoom protocol do not see the robot: a person walking into it from the side or from behind is
// avoided only by moving. This is corridor's addition; the paper's policies react to the camera's view alone.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/safety/obstacle_memory.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct EvasionOptions {
  double robot_radius_m = 0.2;
  double margin_m = 0.2;             // kept between the robot and a moving object, both as discs
  // A laser sees the near side of a person only: an object counts at least this large, its centre this much of
  // the radius beyond the seen centroid (the centroid of a half circle's rim is 2/pi of the radius from its centre).
  double min_object_radius_m = 0.25;
  double far_side_fraction = 0.64;
  double horizon_s = 3.0;            // moving objects are predicted this far
  // People change course (around each other, at the ends of their walks): the margin grows by this much per
  // second of prediction, so that the robot steps farther out of the way of what is farther ahead.
  double uncertainty_mps = 0.1;
  double static_horizon_s = 1.0;     // static points are swept this far
  double static_margin_m = 0.05;
  double step_s = 0.1;
  double max_linear_mps = 0.26;
  double max_reverse_mps = 0.2;     // the laser sees behind: backing away is often the shortest way out
  double max_turn_rps = 1.0;
  double static_reach_m = 2.0;       // static points farther than this cannot matter within the horizon
};

struct EvasionResult {
  Twist2 twist;
  bool evading = false;              // the command was in conflict and was replaced
  double conflict_s = 0.0;           // when the chosen twist's conflict begins (infinity: none within the horizon)
};

class Evasion {
 public:
  explicit Evasion(const EvasionOptions& options);  // throws std::invalid_argument for bad options

  // `command` if it keeps clear of every moving object in `objects` for the horizon; else the best candidate.
  // `static_points` (world frame) and `memory` (may be null) are what must not be driven into.
  EvasionResult Check(const Pose2& robot, const Twist2& command, const std::vector<TrackedObject>& objects,
                      const std::vector<Eigen::Vector2d>& static_points, const ObstacleMemory* memory) const;

  const EvasionOptions& options() const { return options_; }

 private:
  // Turn in place by turn_rad at max_turn_rps, then drive `drive`.
  struct Manoeuvre {
    double turn_rad = 0.0;
    Twist2 drive;
  };
  struct Mover {
    Eigen::Vector2d position;
    Eigen::Vector2d velocity;
    double clearance_m;
  };
  struct Score {
    double conflict_s;   // first conflict time; infinity when none
    double closest_m;    // the smallest gap over the horizon (negative: overlapping)
  };
  Eigen::Vector2d At(const Pose2& robot, const Manoeuvre& m, double t) const;
  Twist2 FirstTwist(const Manoeuvre& m) const;
  Score Predict(const Pose2& robot, const Manoeuvre& m, const std::vector<Mover>& movers) const;
  bool StaticBlocked(const Pose2& robot, const Manoeuvre& m, const std::vector<Eigen::Vector2d>& near,
                     const ObstacleMemory* memory) const;

  EvasionOptions options_;
};

}  // namespace corridor::nav
