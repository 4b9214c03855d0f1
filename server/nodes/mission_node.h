// Runs missions on the bus: feeds the mission runner (nav/mission/mission_runner.h) with each depth frame's view
// (ground/lanes), the robot's pose, what the tracker shows and the bumps the control node reports, on the control
// executor, and carries out what it asks: plans and path checks on the planner service, the command on
// mission/command (once per frame: the control loop runs at the camera's rate), the mission's state on mission and,
// when its status or leg changes, on mission/changes (every change, for the database), and a lift's arrival on
// another floor on mission/floor_arrival (FloorNode switches the map). A timer at 20 Hz does the rest (planning,
// checking the path, holding still when frames stop). Each local step also goes out on mission/step, for traces and the
// console. The doors to have opened and the building's lifts come with the map in use (topics::kMapInUse).
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nav/mission/mission_runner.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

enum class MissionStep { kPause, kResume, kCancel };
const char* ToString(MissionStep step);

class MissionNode final : public PeriodicNode {
 public:
  // The docking goal to the dock nearest the robot (at `robot`, map frame) on the active map, if there is one.
  using DockFinder = std::function<std::optional<nav::MissionGoal>(const nav::Pose2& robot)>;
  // Throws std::invalid_argument for bad options.
  MissionNode(Executor& control, Bus& bus, PlannerService& planner, const nav::MissionRunnerOptions& options);
  void Activate() override;

  // Commands: each is carried out on the node's executor (the control loop's, so that the loop never waits on a
  // lock), in the order they were given, and `done` is told there; it must hand its work elsewhere and not throw.
  // Starting a mission cancels the one in progress; a robot on its dock backs off it first. `done` gets the new
  // mission's state.
  void Start(std::vector<nav::MissionGoal> goals, double speed_limit_mps, std::function<void(MissionState)> done);
  struct Outcome {
    nav::TransitionOutcome outcome;
    std::optional<MissionState> mission;  // its state afterwards, when it is the current (or last) one
  };
  // Appends goals to the mission `id` while it runs (kConflict once it has finished).
  void Extend(const std::string& id, std::vector<nav::MissionGoal> goals, std::function<void(Outcome)> done);
  // Pauses, resumes or cancels mission `id`; `done` may be empty.
  void Step(MissionStep step, const std::string& id, std::function<void(Outcome)> done);
  // The robot stands on its dock (nav::MissionRunner::docked), as of the node's last step. Thread-safe.
  bool docked() const { return docked_; }

 private:
  void Tick() override;
  void Frame(const GroundLanes& ground);
  void Battery(const drivers::BatteryState& battery);  // on its charger or not (docking needs to know)
  Outcome OutcomeOf(const std::string& id, nav::TransitionOutcome outcome) const;
  // Carries out what the runner asked; `frame_arrival_ns`: the frame a command answers, if any.
  void Carry(const nav::MissionUpdate& update, drivers::TimeNs frame_arrival_ns = -1);
  double now_s() const { return drivers::ToSeconds(clock().Now()); }

  PlannerService& planner_;
  LoopStats& plan_loop_;
  std::atomic<bool> docked_{false};
  bool looking_around_ = false;  // turning on the spot for localization
  nav::DockingOptions docking_;
  nav::MissionRunner runner_;
  nav::DoorReports door_reports_;  // what the door controller says
  nav::LiftReports lift_reports_;  // what the lift controller says

  // The topics it reads and writes, resolved once.
  Topic<Bumped>& bumped_topic_ = bus().Get(topics::kBumped);
  Topic<DoorRequests>& door_requests_topic_ = bus().Get(topics::kDoorRequests);
  Topic<LiftRequests>& lift_requests_topic_ = bus().Get(topics::kLiftRequests);
  Topic<LocalStepState>& local_step_topic_ = bus().Get(topics::kLocalStep);
  Topic<LocalizationCommand>& localization_command_topic_ = bus().Get(topics::kLocalizationCommand);
  Topic<MissionState>& mission_topic_ = bus().Get(topics::kMission);
  Topic<MissionState>& changes_topic_ = bus().Get(topics::kMissionChanges);
  Topic<FloorArrival>& floor_topic_ = bus().Get(topics::kFloorArrival);
  Topic<MissionCommand>& mission_command_topic_ = bus().Get(topics::kMissionCommand);
  Topic<drivers::WheelOdometry>& odometry_topic_ = bus().Get(topics::kOdometry);
  Topic<StampedPose>& pose_topic_ = bus().Get(topics::kPose);
  Topic<TrackedObjects>& tracked_objects_topic_ = bus().Get(topics::kTrackedObjects);
};

}  // namespace corridor::server
