// Runs a mission's legs: plans each leg from the robot's pose, drives it with the local policy (local_policy.h) on
// every depth frame, and goes on to the next waypoint. It plans the leg again when the map or zones have changed
// across the rest of the path, when the robot has strayed far from it, and, where people's ways are known, every
// reroute_s, taking the new path when it goes another way; when the robot made no headway for stuck_s it plans round
// what blocked it. It fails the mission with the planner's reason when there is no way, and holds the robot still
// when it has no pose, no path or no depth frames.
//
// Pure logic: the caller (server/nodes/mission_node.h) hands in the clock's time, the robot's pose, each frame and
// what the tracker shows; carries out the plans and path checks an update asks for, handing the answers back
// (OnPlan, OnCheck); and sends the commands. Not thread-safe: one owner.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nav/mission/docking.h"
#include "nav/mission/doors.h"
#include "nav/mission/lifts.h"
#include "nav/mission/mission.h"
#include "nav/planner/costmap.h"
#include "nav/planner/planner.h"
#include "nav/policy/local_navigator.h"
#include "nav/policy/local_policy.h"
#include "nav/policy/reactive.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct MissionRunnerOptions {
  LocalNavigatorOptions navigator;  // morp-rb's, and the replanning rules both policies follow
  LocalPolicyKind policy = LocalPolicyKind::kMorpRb;
  ReactiveOptions reactive;       // voxel-reactive's controller
  double no_frames_s = 0.2;       // no depth frame for this long: hold the robot still
  double stale_tracking_s = 0.3;  // tracked objects older than this are not used (three scans of a 10 Hz laser)
  double fresh_bump_s = 0.5;      // a bump older than this (from before the mission, say) is not where it is now
  DockingOptions docking;         // docking and undocking goals
  DoorOptions doors;              // doors on the way: asked ahead, waited for, released
  LiftOptions lifts;              // lift rides between floors
  // A mission that cannot go on ends, saying why: no headway toward its waypoint (neither the path left nor the
  // straight-line distance fell headway_m below its lowest since the waypoint became current, whatever was replanned)
  // for give_up_s while driving fails it (0: never). A detour longer than give_up_s allows at the robot's speed before
  // it gets nearer in either measure is given up too. Waiting for a door, a lift, localization or a person's resume
  // does not count.
  double give_up_s = 60.0;
  double headway_m = 0.3;
  // Also: blocked (the local policy's no headway, and a plan round what blocked it) this many times in a row within
  // blocked_area_m of where it first was (0: never). A robot that circles in front of a closed way makes headway on
  // each new path for a while, never for long.
  int give_up_blocked = 4;
  double blocked_area_m = 1.5;
  double waiting_after_s = 5.0;  // no headway this long: the snapshot says what the robot waits for
};

// How the robot is driving its mission, as the console shows it.
enum class PolicyMode {
  kNone,
  kFollow,  // morp-rb's modes (MorpRbMode)
  kChangeLaneLeft,
  kChangeLaneRight,
  kStopAndTurn,
  kOvertake,
  kEvade,            // stepping out of a tracked person's way
  kReactive,         // voxel-reactive
  kLearned,          // morp-il's or takiguchi's network
  kWaitingForDepth,  // no depth frames: holding still
  kWaitingForDoor,   // short of a door that is not open yet
};
const char* ToString(PolicyMode mode);

// The mission as the console and the API show it.
struct MissionSnapshot {
  std::string id;
  MissionStatus status = MissionStatus::kActive;
  std::vector<MissionGoal> goals;
  std::size_t current = 0;
  double progress = 0.0;
  double eta_s = 0.0;
  double remaining_on_leg_m = 0.0;
  std::vector<Pose2> path;  // the current leg's waypoints
  PolicyMode policy = PolicyMode::kNone;
  std::string error;
  double speed_limit_mps = 0.0;  // +infinity: none
  std::string docking;           // the current goal's docking phase (DockingPhase), "" when not docking
  std::string waiting_for_door;  // the door the robot holds short of, "" when none
  std::string lift;              // the current goal's lift ride phase (LiftPhase), "" when not riding
  // What an unfinished mission waits for, for people ("a way past what blocks it (no headway for 12 s)", "door d1 to
  // open", "localization: the robot is lost"); "" while it goes on.
  std::string waiting;
};

// A path for the current leg, to plan on the current costmap with ExtraCosts(traffic, blocking...).
struct LegPlanQuery {
  std::uint64_t ticket = 0;
  bool reroute = false;  // a second opinion on a path the robot has: taken when it goes another way, or `blocked`
  bool blocked = false;  // round what blocked the robot: taken whatever its way
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  // the robot's position: what is under it is passable
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  std::optional<double> goal_yaw;
  std::vector<Eigen::Vector2d> blocking;  // LocalPolicy::Blocking
  double blocking_radius_m = 0.0;
  float blocking_cost = 0.0f;
};

// Does the current path still stand on the newest map and zones? RestOfPathTraversable on the current costmap.
struct PathCheckQuery {
  std::uint64_t ticket = 0;
  std::vector<Waypoint> path;
  Eigen::Vector2d from = Eigen::Vector2d::Zero();
};

// What a call asks of the caller.
struct MissionUpdate {
  std::optional<Twist2> command;  // for the command gate; none: send nothing
  bool answers_frame = false;     // the command answers the frame given (its latency counts)
  bool publish = false;           // the snapshot changed: publish it
  bool persist = false;           // the mission's status, leg or path changed: publish and store it
  bool over = false;              // the mission has just finished: the robot is no longer driven by it
  std::optional<LegPlanQuery> plan;
  std::optional<PathCheckQuery> check;
  std::optional<LocalStep> step;   // this frame's local step (traces)
  bool docking = false;            // the command drives onto (or off) a dock: the gate lets it near the dock's face
  std::vector<DoorRequest> doors;  // for the door controller: open these, release those
  std::vector<LiftRequest> lifts;  // for the lift controller
  // A lift arrived on another floor: switch to that floor's map, with the robot at this pose in it.
  std::optional<std::pair<std::string, Pose2>> switch_floor;
  // Boarding, riding and leaving a lift, localization holds on odometry (true) and resumes after (false): the car's
  // walls are in no map and its floor changes under the robot.
  std::optional<bool> hold_localization;
};

// One depth frame, as the runner takes it.
struct FrameInput {
  double now_s = 0.0;
  std::optional<Pose2> pose;  // the robot in the map frame; none yet
  std::optional<Pose2> odom;  // the robot in the odometry frame (docking drives on it); none yet
  FrameView view;
  const Surroundings* tracked = nullptr;  // the tracker's latest (may be null)
  double tracked_received_s = 0.0;        // when the tracker made it
  std::optional<double> bump_s;           // the latest bump the control node reported, and which way
  bool bump_backing = false;
  const DoorReports* doors = nullptr;  // what the door controller says of each door (null: nothing yet)
  const LiftReports* lifts = nullptr;  // what the lift controller says of each lift (null: nothing yet)
};

enum class TransitionOutcome { kOk, kNotFound, kConflict };

class MissionRunner {
 public:
  // Throws std::invalid_argument for bad navigator options.
  explicit MissionRunner(const MissionRunnerOptions& options);

  // Starts `mission`, cancelling the one in progress (its snapshot is then published and stored first: `cancelled`).
  MissionUpdate Start(Mission mission, std::optional<MissionSnapshot>* cancelled = nullptr);
  // Pausing keeps the path; resuming plans the leg again from where the robot is (it may have been pushed or driven
  // while paused); cancelling drops it.
  // More goals after the last (an order extended); kConflict once the mission has finished (or for no goals).
  TransitionOutcome Extend(const std::string& id, std::vector<MissionGoal> goals, MissionUpdate* update);
  TransitionOutcome Pause(const std::string& id, MissionUpdate* update);
  TransitionOutcome Resume(const std::string& id, MissionUpdate* update);
  TransitionOutcome Cancel(const std::string& id, MissionUpdate* update);
  // Localization lost (localized false) pauses an active mission: a robot that does not know where it is stops. Found
  // again, the mission it paused resumes; a mission paused by a person stays paused.
  MissionUpdate SetLocalized(bool localized);

  // The periodic check (the node's timer): plans, path checks, reroutes, and holding still without frames.
  MissionUpdate Tick(double now_s, const std::optional<Pose2>& pose, std::uint64_t planner_version, bool has_traffic);
  // One local step on a depth frame.
  MissionUpdate Frame(const FrameInput& frame);
  // The answer to a plan query: `version` is the map and zones' it was planned on, `costmap` what it was planned on.
  MissionUpdate OnPlan(const LegPlanQuery& query, const PlanResult& result, std::shared_ptr<const Costmap> costmap,
                       std::uint64_t version, double now_s);
  MissionUpdate OnCheck(const PathCheckQuery& query, bool still_free, std::shared_ptr<const Costmap> costmap,
                        std::uint64_t version);

  // The robot stands on a dock: it docked, or the charger says so (SetOnCharger). A mission that starts there backs
  // off the dock first (the node adds the undocking goal).
  bool docked() const { return docked_; }
  void SetOnCharger(bool on_charger);

  // The doors of the map the robot is on (the planner's map): paths through them are asked for.
  void SetDoors(std::vector<Door> doors) { doors_ = std::move(doors); }
  // The building's floors and lifts: ride goals (GoalAction::kRideLift) name its lifts.
  void SetBuilding(Building building) { building_ = std::move(building); }

  bool has_mission() const { return mission_.has_value(); }
  // A mission was cancelled with the robot in a lift's car: it is still on its way out (LiftRide::WindUp). No new
  // mission may start until it is out.
  bool leaving_lift() const { return ride_ && ride_->winding_up(); }
  // No mission under way, or the current one paused because localization is lost: the robot may turn on the spot to
  // find itself (a mission a person paused keeps the robot still).
  bool MayLookAround() const { return !leaving_lift() && (!mission_ || mission_->finished() || paused_unlocalized_); }
  const std::string& id() const;     // "" without a mission
  MissionSnapshot Snapshot() const;  // requires has_mission()
  const LocalPolicy& policy() const { return *policy_; }

 private:
  bool paused_unlocalized_ = false;  // the current mission was paused by SetLocalized(false)
  double now_s_ = 0.0;               // the latest time given (a tick or a frame)
  // Headway toward the current waypoint: the lowest distance left on any path to it and the lowest straight-line
  // distance to it, and when either last fell by headway_m (negative: not counting, as while waiting for a door).
  double best_remaining_m_ = std::numeric_limits<double>::infinity();
  double best_direct_m_ = std::numeric_limits<double>::infinity();
  double headway_s_ = -1.0;
  std::optional<Eigen::Vector2d> blocked_at_;  // where the current run of blocked reports began
  int blocked_count_ = 0;
  void ResetHeadway() {
    best_remaining_m_ = best_direct_m_ = std::numeric_limits<double>::infinity();
    headway_s_ = -1.0;
    blocked_at_.reset();
    blocked_count_ = 0;
  }
  // Fails the mission: no way forward near `pose`, for `why`.
  void GiveUp(const Pose2& pose, const std::string& why, MissionUpdate& update);
  std::string Waiting() const;
  LegPlanQuery LegQuery(const Pose2& from, bool reroute, bool blocked) const;
  // The current path is dropped: the next tick plans the leg again.
  void DropPath();
  TransitionOutcome Transition(const std::string& id, bool (Mission::*transition)(), bool drop_path,
                               MissionUpdate* update);
  bool Current(std::uint64_t ticket) const { return ticket == generation_ && mission_ && !mission_->finished(); }
  // Frame and OnPlan before their doors are settled (Settle).
  MissionUpdate FrameStep(const FrameInput& frame);
  MissionUpdate PlanAnswered(const LegPlanQuery& query, const PlanResult& result,
                             std::shared_ptr<const Costmap> costmap, std::uint64_t version, double now_s);
  // A frame while docking or undocking.
  MissionUpdate DockingFrame(const FrameInput& frame);
  // A frame while riding a lift (boarding, riding, leaving).
  MissionUpdate LiftFrame(const FrameInput& frame);
  // The current goal is reached: on to the next (a brief stop first) or done.
  void NextGoal(MissionUpdate& update);
  bool AtDockingGoal() const {
    return docking_ || (mission_ && !mission_->finished() && mission_->current_goal().action == GoalAction::kUndock);
  }
  // Driving on frames alone, not on a planned path: docking, undocking or riding a lift.
  bool OffPath() const { return AtDockingGoal() || ride_.has_value(); }

  MissionRunnerOptions options_;
  std::unique_ptr<LocalPolicy> policy_;
  std::optional<Mission> mission_;
  std::uint64_t generation_ = 0;  // bumped per leg and mission, to drop answers to stale queries
  bool planning_ = false;
  bool checking_ = false;
  bool rerouting_ = false;
  double routed_s_ = 0.0;           // when the current path was planned or last checked against people's ways
  std::uint64_t path_version_ = 0;  // planner version the current path was made or checked with
  double leg_length_m_ = 0.0;
  double remaining_m_ = 0.0;
  double last_frame_s_ = -1.0;  // negative: none yet
  double bump_seen_s_ = -1e300;
  PolicyMode mode_ = PolicyMode::kNone;
  std::optional<Docking> docking_;  // docking or undocking at the current goal
  DockingPhase docking_phase_ = DockingPhase::kSeeking;
  bool docked_ = false;
  std::vector<Door> doors_;
  DoorKeeper door_keeper_;
  std::string waiting_for_door_;
  Building building_;
  std::optional<LiftRide> ride_;  // riding a lift at the current goal
  // The current path is `waypoints`: which doors it crosses.
  void PathSet(const std::vector<Waypoint>& waypoints, MissionUpdate& update);
  // Over: the doors and the lift still asked for are released.
  MissionUpdate& Settle(MissionUpdate& update);
  void ReleaseAll(MissionUpdate& update);
};

}  // namespace corridor::nav
