// The robot core: the one way in for commands that move the robot or say where it is, whichever interface they
// arrive through (REST and the stream, DDS, VDA 5050, Open-RMF). A command is checked by pure code in nav/ (a
// mission's goals: nav/mission/goal_check.h) and answered with its result or a typed refusal, which each interface
// words in its own vocabulary at its edge: problem+json with a status code, a VDA 5050 error naming the node, a
// refusal logged for DDS. Nothing moves on a refusal. No interface starts a mission or sets the pose another way.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "nav/mission/goal_check.h"
#include "nav/mission/mission.h"
#include "server/nodes/localization_node.h"
#include "server/nodes/mission_node.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/config.h"
#include "server/runtime/messages.h"
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

enum class MissionStep { kPause, kResume, kCancel };
const char* ToString(MissionStep step);

class RobotCore {
 public:
  RobotCore(const Config& config, PlannerService& planner, MissionNode& missions, LocalizationNode& localization,
            const MapLibrary& maps, const Store& store);

  // Checks the goals against the map in use (its costmap, with keep-out zones, made on the planning executor) and
  // the building, then starts the mission (replacing the one in progress) or refuses it. `done` is called once, on
  // the planning executor, and must not throw.
  void StartMission(MissionOrder order, std::function<void(MissionResult)> done) const;
  // Gives localization the pose, or refuses it. `done` is called once (on the calling thread for a refusal, else on
  // localization's executor) and must not throw.
  void SetPose(const PoseOrder& order, std::function<void(PoseResult)> done) const;
  // Pauses, resumes or cancels mission `id`: kNotFound when no such mission is in progress, kConflict when its status
  // does not allow it (resuming an active one). Thread-safe.
  nav::TransitionOutcome Command(MissionStep step, const std::string& id, std::string_view origin) const;
  // Why `pose` is not on the map in use ("(x, y) is not on map 'name'"), or nothing when it is.
  std::optional<std::string> OffMap(const nav::Pose2& pose) const;

 private:
  const Config& config_;
  PlannerService& planner_;
  MissionNode& missions_;
  LocalizationNode& localization_;
  const MapLibrary& maps_;
  const Store& store_;
};

}  // namespace corridor::server
