// Stepping out of the way of people: the last check on a command before it goes out, when a laser tracks moving
// objects around the robot (nav/tracking/moving_objects.h).
//
// Each moving object is predicted at constant velocity for a horizon, the robot along a manoeuvre; a manoeuvre is in
// conflict when the two footprints (with a margin that grows with the prediction time) come closer than that while
// still closing in. A command without conflict passes unchanged. Otherwise a dynamic window (Fox, Burgard and
// Thrun, 1997) with velocity obstacles' prediction (Fiorini and Shiller, 1998) is searched over two-part
// manoeuvres: one twist for the first second, another for the rest of the horizon (so "wait, then cross behind
// them" and "turn away, then drive on" are in the set, which a single arc cannot express for a differential base).
// Of the manoeuvres without conflict that keep clear of what stands still (the scan's static points and the obstacle
// memory), the one making the most progress toward the target wins, less a penalty for passing close to people and
// for leaving the command; if none is without conflict, the one keeping the closest approach widest. Its first twist
// goes out, and the search is made again on the next frame.
//
// People in the DPoom protocol do not see the robot: a person walking into it from the side or from behind is
// avoided only by moving. This is corridor's addition; the paper's policies react to the camera's view alone.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/safety/obstacle_memory.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct EvasionOptions {
  double robot_radius_m = 0.2;
  double margin_m = 0.3;  // kept between the robot and a moving object, both as discs
  // A laser sees the near side of a person only: an object counts at least this large, its centre this much of
  // the radius beyond the seen centroid (the centroid of a half circle's rim is 2/pi of the radius from its centre).
  double min_object_radius_m = 0.25;
  double far_side_fraction = 0.64;
  double horizon_s = 3.0;  // moving objects are predicted this far
  // People change course (around each other, at the ends of their walks): the margin grows by this much per
  // second of prediction, so that the robot steps farther out of the way of what is farther ahead.
  double uncertainty_mps = 0.1;
  // A person walking away may turn round at any moment (at the end of their walk; people pace): one walking away
  // with the robot in their wake (within the clearance of their line) and within turn_reach_m of it is also
  // predicted walking back at the same speed, for turn_horizon_s, so that the robot does not follow closer than it
  // could get out of the way (0: off).
  double turn_reach_m = 2.0;
  double turn_horizon_s = 1.5;
  // A person walking toward the known end of their walk (TrackedObject::turn_at) is predicted to turn round there,
  // this far beyond it (people do not turn at the very same spot), and walk back; for them the guess above is not
  // made.
  double walk_end_slack_m = 0.2;
  double static_horizon_s = 1.0;  // static points are swept this far
  double static_margin_m = 0.05;
  double step_s = 0.1;
  double max_linear_mps = 0.26;
  double max_reverse_mps = 0.2;  // the laser sees behind: backing away is often the shortest way out
  double max_turn_rps = 1.0;
  double static_reach_m = 2.0;  // static points farther than this cannot matter within the horizon
  double first_s = 1.0;         // the first part of a manoeuvre; the second lasts to the horizon
  double social_m = 0.3;        // passing a person with less than this beyond the margin costs...
  double social_weight = 1.0;   // ...this much per metre short of it, against metres of progress
  double smooth_weight = 0.2;   // and leaving the command costs this per m/s (and per 3 rad/s);
  double commit_bonus = 0.15;   // keeping the previous frame's evasive twist is worth this: a way out chosen
                                // is followed, not swapped for its mirror image on the next frame
};

struct EvasionResult {
  Twist2 twist;
  bool evading = false;     // the command was in conflict and was replaced
  double conflict_s = 0.0;  // when the chosen twist's conflict begins (infinity: none within the horizon)
};

// The options for a robot that sees only ahead (a depth camera and no laser): what is behind it is unknown, so
// evasion never backs.
EvasionOptions ForForwardView(EvasionOptions options);

class Evasion {
 public:
  explicit Evasion(const EvasionOptions& options);  // throws std::invalid_argument for bad options

  // `command` if it keeps clear of every moving object in `objects` for the horizon; else the first twist of the
  // best manoeuvre toward `target` (world frame; the robot's own position: no preference). `static_points` (world
  // frame) and `memory` (may be null) are what must not be driven into.
  // Remembers its choice for the next call's commit_bonus.
  EvasionResult Check(const Pose2& robot, const Twist2& command, const Eigen::Vector2d& target,
                      const std::vector<TrackedObject>& objects, const std::vector<Eigen::Vector2d>& static_points,
                      const ObstacleMemory* memory);

  const EvasionOptions& options() const { return options_; }

 private:
  struct Mover {
    Eigen::Vector2d position;
    Eigen::Vector2d velocity;
    double clearance_m;
    int steps;      // predicted this many steps of the horizon
    double turn_s;  // turning round (walking back at the same speed) after this long; infinity: never
    Eigen::Vector2d At(double t) const { return position + velocity * (t <= turn_s ? t : 2.0 * turn_s - t); }
  };
  struct Score {
    double conflict_s;  // first conflict time; infinity when none
    double closest_m;   // the smallest gap over the horizon (negative: overlapping)
  };
  // The movers' predicted places, made once a decision: path[i][k - 1] is mover i's at step k (of its steps).
  using Paths = std::vector<std::vector<Eigen::Vector2d>>;
  // The places `twist` takes the robot in 1 .. steps_ steps, in the frame it starts in.
  std::vector<Eigen::Vector2d> Chord(const Twist2& twist) const;
  // Where the robot is at steps from_step + 1 .. steps_ (at[k - 1] for step k) driving the twist whose arc is
  // `chord` (chord[j - 1]: j steps of it, in the frame it starts in) from `start`, where it is at step from_step;
  // earlier steps of `at` are left as they are.
  void Trace(const Pose2& start, const std::vector<Eigen::Vector2d>& chord, int from_step,
             std::vector<Eigen::Vector2d>& at) const;
  // `score` carried on over steps from_step + 1 .. to_step of the robot's places `at`; gaps[i] is mover i's gap at
  // from_step on entry, at to_step on return.
  Score Predict(const std::vector<Eigen::Vector2d>& at, const std::vector<Mover>& movers, const Paths& paths,
                int from_step, int to_step, Score score, std::vector<double>& gaps) const;
  bool StaticBlocked(const Pose2& robot, const std::vector<Eigen::Vector2d>& at, int steps,
                     const std::vector<Eigen::Vector2d>& near) const;

  int steps_;                   // prediction steps over the horizon
  int first_steps_;             // of them, the first part's
  int turn_steps_;              // of them, those a person walking away is also predicted walking back
  std::vector<Twist2> twists_;  // each part of a manoeuvre drives one of these
  // chords_[i][j - 1]: where twists_[i] takes the robot in j steps, in the frame it started in (j = 1 .. steps_)
  std::vector<std::vector<Eigen::Vector2d>> chords_;
  std::optional<Twist2> last_;  // the previous call's evasive twist; none when it did not evade
  EvasionOptions options_;
};

}  // namespace corridor::nav
