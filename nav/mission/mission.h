// A mission: one goal or a list of waypoints, each with an optional heading, driven in order. This is the pure
// bookkeeping (status, which waypoint, progress, ETA); planning and driving are the mission node's.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

enum class MissionStatus { kActive, kPaused, kSucceeded, kFailed, kCanceled };
const char* ToString(MissionStatus status);
// Active or paused: not over, its goals still the robot's.
inline bool InProgress(MissionStatus status) {
  return status == MissionStatus::kActive || status == MissionStatus::kPaused;
}

// What the robot does at a goal: stop there, dock (drive to the dock's staging pose, `pose`, then onto the dock at
// `dock`), back off the dock it stands on (no pose: it backs straight off), or ride a lift (drive to its lobby,
// `pose`, then board and ride to `ride_to`: nav/mission/lifts.h).
enum class GoalAction { kGo, kDock, kUndock, kRideLift };
const char* ToString(GoalAction action);

struct MissionGoal {
  Pose2 pose;  // yaw used only when has_yaw
  bool has_yaw = false;
  std::string place;  // the named place it came from, if any
  GoalAction action = GoalAction::kGo;
  Pose2 dock;                                                      // kDock: the docked pose (map frame)
  double max_speed_mps = std::numeric_limits<double>::infinity();  // on the leg to this goal, below the mission's
  std::string floor;    // the floor the goal is on; "": the floor of the goal before it (or the robot's)
  std::string lift;     // kRideLift: the lift
  std::string ride_to;  // kRideLift: the floor it rides to
};

class Mission {
 public:
  // Requires at least one goal; speed_limit_mps may be +infinity.
  Mission(std::string id, std::vector<MissionGoal> goals, double speed_limit_mps);

  const std::string& id() const { return id_; }
  MissionStatus status() const { return status_; }
  bool finished() const {
    return status_ == MissionStatus::kSucceeded || status_ == MissionStatus::kFailed ||
           status_ == MissionStatus::kCanceled;
  }
  const std::vector<MissionGoal>& goals() const { return goals_; }
  std::size_t current() const { return current_; }
  const MissionGoal& current_goal() const { return goals_[current_]; }
  double speed_limit_mps() const { return speed_limit_mps_; }
  const std::string& error() const { return error_; }

  // Transitions; each returns false (and changes nothing) when not allowed from the current status.
  bool Pause();
  bool Resume();
  bool Cancel();
  // The current goal is reached: on to the next, or succeeded after the last.
  void GoalReached();
  void Fail(std::string reason);
  // More goals after the last; false (and nothing changes) once the mission has finished.
  bool Extend(std::vector<MissionGoal> goals);

  // Fraction done in [0, 1], counting finished goals and the part of the current leg already driven.
  double Progress(double remaining_on_leg_m, double leg_length_m) const;
  // Seconds to the last goal at `speed_mps`: the current leg's remaining length plus straight lines between the
  // remaining goals (a lower bound: their paths are planned when reached).
  double EtaSeconds(double remaining_on_leg_m, double speed_mps) const;

 private:
  std::string id_;
  std::vector<MissionGoal> goals_;
  double speed_limit_mps_;
  MissionStatus status_ = MissionStatus::kActive;
  std::size_t current_ = 0;
  std::string error_;
};

}  // namespace corridor::nav
