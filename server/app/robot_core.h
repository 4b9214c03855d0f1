// The robot core: the one way in for commands that move the robot or say where it is, whichever interface they
// arrive through (REST and the stream, DDS, VDA 5050, Open-RMF). A command is checked by pure code in nav/ (a
// mission's goals: nav/mission/goal_check.h) and answered with its result or a typed refusal, which each interface
// words in its own vocabulary at its edge: problem+json with a status code, a VDA 5050 error naming the node, a
// refusal logged for DDS. Nothing moves on a refusal. No interface starts a mission or sets the pose another way.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "nav/mission/goal_check.h"
#include "nav/mission/mission.h"
#include "server/app/robot_state.h"
#include "server/config/config.h"
#include "server/nodes/localization_node.h"
#include "server/nodes/mission_node.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/messages.h"
#include "server/runtime/node.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

// The building as the robot uses it: the configuration's floors and lifts, with the lift stops drawn in the console
// (the store's) put in.
nav::Building CurrentBuilding(const Config& config, const Store& store);

struct MissionOrder {
  std::vector<nav::MissionGoal> goals;  // at least one
  double speed_limit_mps = std::numeric_limits<double>::infinity();
  std::string origin;  // who asks ("rest", "dds", "vda5050", ...), for the log
};
using MissionResult = std::variant<MissionState, nav::MissionRefusal>;
// kOk: the running mission took the goals; kNotFound or kConflict: it is not running (any more) and nothing changed.
using ExtendResult = std::variant<nav::TransitionOutcome, nav::MissionRefusal>;

enum class MapRefusal {
  kMissionInProgress,  // a mission is active or paused: its goals are on the map in use
  kUnusable,           // no such map, or it cannot be read
};
struct MapRefused {
  MapRefusal reason = MapRefusal::kUnusable;
  std::string detail;
};

enum class PoseRefusal {
  kNotLocalizing,  // localization.source is not mcl: nothing takes a pose
  kOutsideMap,     // the pose is off the map in use
  kBadSpread,      // sigma_m outside [0, 10] m or sigma_rad outside [0, pi]
  kBusy,           // localization will not take one now (mapping under way)
};
struct PoseRefused {
  PoseRefusal reason = PoseRefusal::kOutsideMap;
  std::string detail;  // a sentence for people
};
struct PoseOrder {
  nav::Pose2 pose;  // map frame
  double sigma_m = LocalizationCommand{}.sigma_m;
  double sigma_rad = LocalizationCommand{}.sigma_rad;
  std::string origin;
};
using PoseResult = std::variant<PoseCheck, PoseRefused>;

enum class MappingRefusal {
  kNotLocalizing,   // localization.source is not mcl: nothing maps or relocalizes
  kMapExists,       // a map of that name exists
  kAlreadyMapping,  // mapping is under way
  kNotMapping,      // nothing to stop
};
struct MappingRefused {
  MappingRefusal reason = MappingRefusal::kNotMapping;
  std::string detail;  // a sentence for people
};

// Whether anyone opens the doors on the robot's way: the building's controller, or in a simulated world with doors
// and no controller, the simulator's doors themselves. Without either the robot drives as it sees them.
inline bool DoorsAnswer(const Config& config) {
  return config.doors.controller.configured() || (Simulated(config) && !config.sim.robot.doors.empty());
}
// Something answers lift calls: the building's controller, or in a simulated building that names none, the
// simulator's lifts themselves (the graph's LiftNode then talks to one of them).
inline bool LiftsAnswer(const Config& config) {
  return config.building.controller.configured() || (Simulated(config) && !config.building.lifts.empty());
}

// The map in use with its zones, the doors missions ask to have opened on it (none when nothing answers:
// DoorsAnswer) and the building with its lift stops: what topics::kMapInUse carries.
MapInUse MapInUseOf(const std::shared_ptr<const ActiveMap>& map, const Config& config, const Store& store);

class RobotCore {
 public:
  RobotCore(const Config& config, Bus& bus, const drivers::Clock& clock, const Lifecycle& lifecycle,
            PlannerService& planner, MissionNode& missions, LocalizationNode& localization, MapLibrary& maps,
            const Store& store);

  // The robot's state now: taken at most once a tick (1 / server.stream_rate_hz of the graph's clock, and again after
  // any command through the core or a change of the map in use), shared by every reader in that tick. Thread-safe.
  std::shared_ptr<const RobotState> State() const;

  // Checks the goals against the map in use (its costmap, with keep-out zones, made on the planning executor) and
  // the building, then starts the mission (replacing the one in progress) or refuses it. `done` is called once, on
  // the planning executor (a refusal) or the control executor (the mission started), and must not throw.
  void StartMission(MissionOrder order, std::function<void(MissionResult)> done) const;
  // Checks `goals` as StartMission does, then appends them to mission `id`. `done` as StartMission's.
  void ExtendMission(const std::string& id, std::vector<nav::MissionGoal> goals, std::string origin,
                     std::function<void(ExtendResult)> done) const;
  // Gives localization the pose, or refuses it. `done` is called once (on the calling thread for a refusal, else on
  // localization's executor) and must not throw.
  void SetPose(const PoseOrder& order, std::function<void(PoseResult)> done) const;
  // Pauses, resumes or cancels mission `id`: kNotFound when no such mission is in progress, kConflict when its status
  // does not allow it (resuming an active one). `done` (may be empty) is told on the control executor, with the
  // mission's state afterwards. Thread-safe.
  void Command(MissionStep step, const std::string& id, std::string_view origin,
               std::function<void(MissionNode::Outcome)> done = {}) const;
  // Stops the robot at once, as an emergency stop button does: zero velocity by hand (the control node takes it over a
  // mission's command at once) and the mission in progress paused, so that it waits to be resumed or cancelled. `done`
  // (may be empty) is told the paused mission's state, or nothing when none was active; once, on the control executor
  // or the calling thread. Thread-safe.
  void Stop(std::string_view origin, std::function<void(std::optional<MissionState>)> done = {}) const;
  // Makes map `name` the one in use (the console's choice, or a floor a fleet adapter took the robot to), or refuses.
  std::optional<MapRefused> SelectMap(const std::string& name, std::string_view origin) const;
  // Mission `id`'s state when it is the current (or last) one, as last published (topics::kMission): its progress
  // for VDA 5050, RMF and REST.
  std::optional<MissionState> Mission(const std::string& id) const;
  // The robot stands on its dock now. Thread-safe.
  bool Docked() const;
  // The docking goal to the dock nearest `robot` (map frame) on the map in use, if the map has a dock.
  std::optional<nav::MissionGoal> NearestDock(const nav::Pose2& robot) const;
  // Why `pose` is not on the map in use ("(x, y) is not on map 'name'"), or nothing when it is.
  std::optional<std::string> OffMap(const nav::Pose2& pose) const;
  // Drives the base by hand (the console's joystick and keys, the stream, ROS 2's cmd_vel): the control node takes
  // it over a mission's command, limits it to safety.max_linear_mps and max_angular_rps, lets the safety gate slow or
  // stop it, and stops the robot when commands stop coming for safety.teleop_deadman_s. Returns the command within
  // those limits. Thread-safe.
  nav::Twist2 Teleop(const nav::Twist2& asked, std::string_view origin) const;
  // Starts mapping a new building under map `name` (a valid map name: its form is the caller's to check), or refuses.
  std::optional<MappingRefused> StartMapping(const std::string& name, std::string_view origin) const;
  // Stops the mapping under way, which saves its map and makes it the map in use: the map's name, or a refusal.
  std::variant<std::string, MappingRefused> StopMapping(std::string_view origin) const;
  // Has localization search the whole map for the robot, or refuses (kNotLocalizing only).
  std::optional<MappingRefused> Relocalize(std::string_view origin) const;
  // Explores the map being built (ExploreNode): mapping is under way, or was started just before. Refuses
  // (kNotLocalizing only) when nothing maps.
  std::optional<MappingRefused> Explore(std::string_view origin) const;
  // Why nothing takes a pose, maps, explores or relocalizes (localization.source is not mcl); nothing when it does.
  std::optional<std::string> NotLocalizing() const;
  // Zones, doors or lift stops of the map in use were edited (`what`): every node takes the map again
  // (topics::kMapInUse), plans and goal checks from the next one queued.
  void MapEdited(std::string_view what, std::string_view origin) const;

 private:
  // The goals against the map in use (its costmap, `costmap`) and the building; on the planning executor.
  nav::GoalCheckResult Check(std::vector<nav::MissionGoal> goals, const nav::Costmap& costmap) const;
  RobotState Take() const;
  // The next State() takes a new one (a command changed what it would say).
  void Stale() const;

  const Config& config_;
  Bus& bus_;
  const drivers::Clock& clock_;
  const Lifecycle& lifecycle_;
  PlannerService& planner_;
  MissionNode& missions_;
  LocalizationNode& localization_;
  MapLibrary& maps_;
  const Store& store_;
  const drivers::TimeNs start_ns_;
  const drivers::TimeNs tick_ns_;
  mutable std::mutex state_mutex_;
  mutable std::shared_ptr<const RobotState> state_;  // the latest taken; null: stale
  mutable ProcessUsage process_;
};

}  // namespace corridor::server
