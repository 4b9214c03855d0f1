// Runs missions: plans each leg from the robot's pose with the planner service, drives it with the local navigator
// (the path follower, and MORP-RB around what the map does not show), and goes on to the next waypoint. Replans
// when the map or zones change across the rest of the path and when the robot has strayed far from it, and, where the
// laser has shown where people walk, every reroute_s, taking the new path when it goes another way; fails the
// mission with the planner's reason when there is no way. On the control executor.
//
// Driving runs once per depth frame, as soon as its lanes arrive (ground/lanes), so the command answers the newest
// frame: the control loop runs at the camera's rate. A timer at 20 Hz does the rest (planning, checking the path,
// stopping when frames stop). Publishes its velocity on mission/command for the control node, and its state on
// mission.
#pragma once

#include <functional>
#include <memory>
#include <mutex>

#include "nav/mission/mission.h"
#include "nav/policy/local_navigator.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class MissionNode final : public PeriodicNode {
 public:
  enum class Outcome { kOk, kNotFound, kConflict };

  // `on_change` receives the mission's document whenever its status changes (to persist it); called on the
  // control executor, so it must hand the work elsewhere.
  MissionNode(Executor& control, Bus& bus, PlannerService& planner,
              const nav::LocalNavigatorOptions& navigator, std::function<void(nlohmann::json)> on_change);
  void Activate() override;

  // Thread-safe. Starting a mission cancels the one in progress. Returns the new mission's document.
  nlohmann::json Start(std::vector<nav::MissionGoal> goals, double speed_limit_mps);
  Outcome Pause(const std::string& id);
  Outcome Resume(const std::string& id);
  Outcome Cancel(const std::string& id);
  // The mission's document when it is the current (or last) one.
  std::optional<nlohmann::json> Describe(const std::string& id) const;

 private:
  void Tick() override;
  void Drive(const GroundLanes& lanes);  // one local navigation step on this frame's lanes
  // Applies a Mission transition to mission `id`; drop_path: the current path no longer applies.
  Outcome Transition(const std::string& id, bool (nav::Mission::*transition)(), bool drop_path);
  // Plans the current leg from `from`; `done` runs on the node's executor with the lock held, told whether the
  // answer is still for this leg of this mission.
  void PlanLeg(const nav::Pose2& from, std::function<void(const PlanReply&, bool current)> done);
  void RequestPlan(const nav::Pose2& from);
  // Plans the leg again from `from` with the planner's newest traffic costs; takes the new path if it goes another
  // way than the current one, or in any case when `blocked` (the navigator made no headway: the new path goes round
  // what blocked it). A failed plan leaves the current path.
  void Reroute(const nav::Pose2& from, bool blocked = false);
  void CheckPath(const nav::Pose2& from);
  nlohmann::json DescribeLocked() const;
  void Changed();  // status changed: persist and publish

  PlannerService& planner_;
  std::function<void(nlohmann::json)> on_change_;
  double nominal_speed_mps_;

  mutable std::mutex mutex_;
  std::unique_ptr<nav::Mission> mission_;
  nav::LocalNavigator navigator_;
  drivers::TimeNs last_drive_ns_ = -1;  // the last Drive, on the node's clock
  drivers::TimeNs bump_seen_ns_ = -1;   // the latest bump remembered
  std::string policy_mode_;
  std::uint64_t generation_ = 0;    // bumped per leg and mission, to drop answers to stale requests
  bool planning_ = false;
  bool checking_ = false;
  bool rerouting_ = false;
  drivers::TimeNs routed_ns_ = 0;   // when the current path was planned or last checked against people's ways
  std::uint64_t path_version_ = 0;  // planner version the current path was made or checked with
  double leg_length_m_ = 0.0;
  double remaining_m_ = 0.0;
};

}  // namespace corridor::server
