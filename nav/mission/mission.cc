#include "nav/mission/mission.h"

#include <algorithm>
#include <stdexcept>

namespace corridor::nav {

const char* ToString(GoalAction action) {
  switch (action) {
    case GoalAction::kGo: return "go";
    case GoalAction::kDock: return "dock";
    case GoalAction::kUndock: return "undock";
    case GoalAction::kRideLift: return "ride_lift";
  }
  return "unknown";
}

const char* ToString(MissionStatus status) {
  switch (status) {
    case MissionStatus::kActive: return "active";
    case MissionStatus::kPaused: return "paused";
    case MissionStatus::kSucceeded: return "succeeded";
    case MissionStatus::kFailed: return "failed";
    case MissionStatus::kCanceled: return "canceled";
  }
  return "unknown";
}

Mission::Mission(std::string id, std::vector<MissionGoal> goals, double speed_limit_mps)
    : id_(std::move(id)), goals_(std::move(goals)), speed_limit_mps_(speed_limit_mps) {
  if (goals_.empty()) throw std::invalid_argument("a mission needs at least one waypoint");
}

bool Mission::Pause() {
  if (status_ != MissionStatus::kActive) return false;
  status_ = MissionStatus::kPaused;
  return true;
}

bool Mission::Resume() {
  if (status_ != MissionStatus::kPaused) return false;
  status_ = MissionStatus::kActive;
  return true;
}

bool Mission::Cancel() {
  if (finished()) return false;
  status_ = MissionStatus::kCanceled;
  return true;
}

void Mission::GoalReached() {
  if (finished()) return;
  if (current_ + 1 < goals_.size()) {
    ++current_;
  } else {
    status_ = MissionStatus::kSucceeded;
  }
}

void Mission::Fail(std::string reason) {
  if (finished()) return;
  status_ = MissionStatus::kFailed;
  error_ = std::move(reason);
}

bool Mission::Extend(std::vector<MissionGoal> goals) {
  if (finished()) return false;
  goals_.insert(goals_.end(), std::make_move_iterator(goals.begin()), std::make_move_iterator(goals.end()));
  return true;
}

double Mission::Progress(double remaining_on_leg_m, double leg_length_m) const {
  if (status_ == MissionStatus::kSucceeded) return 1.0;
  const double leg = leg_length_m > 0.0 ? std::clamp(1.0 - remaining_on_leg_m / leg_length_m, 0.0, 1.0) : 0.0;
  return (static_cast<double>(current_) + leg) / static_cast<double>(goals_.size());
}

double Mission::EtaSeconds(double remaining_on_leg_m, double speed_mps) const {
  if (finished()) return 0.0;
  double distance = remaining_on_leg_m;
  for (std::size_t i = current_ + 1; i < goals_.size(); ++i) {
    distance += (goals_[i].pose.translation() - goals_[i - 1].pose.translation()).norm();
  }
  return speed_mps > 0.0 ? distance / speed_mps : 0.0;
}

}  // namespace corridor::nav
