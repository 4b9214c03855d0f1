// Whether a mission's goals can be driven before anything moves, for every interface alike (REST, the stream, DDS,
// VDA 5050, Open-RMF, exploring, docking): each goal on the map, free and outside keep-out zones (on its own floor's
// map when it is on another floor), and goals on other floors reachable through the building's lifts. Pure: the
// caller hands in the costmap of the map in use and the building; the answer is the goals as the mission runner takes
// them (lift rides put in) or a typed refusal naming the goal, which each interface words in its own vocabulary.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "nav/map/occupancy_grid.h"
#include "nav/mission/lifts.h"
#include "nav/mission/mission.h"
#include "nav/planner/costmap.h"

namespace corridor::nav {

enum class GoalRefusal {
  kOutsideMap,        // the goal lies off its floor's map
  kOccupied,          // in a wall, or too close to one for the robot
  kInKeepOut,         // in a keep-out zone
  kUnknownFloor,      // on a floor the building does not have
  kNotOnFloor,        // goals on floors, but the map in use is no floor of the building
  kNoLiftController,  // goals on other floors, and no lift controller to call the lifts with
  kNoLiftRoute,       // no lift serves both floors
};
// "goal_outside_map", "goal_occupied", "goal_in_keep_out", "unknown_floor", "no_floor", "no_lift", "no_lift_route".
const char* ToString(GoalRefusal refusal);

struct MissionRefusal;
// The refusal as one sentence, the goal called `goal_name` ("waypoints[2]", "node n7").
std::string Describe(const MissionRefusal& refusal, const std::string& goal_name);

struct MissionRefusal {
  GoalRefusal reason = GoalRefusal::kOccupied;
  std::optional<std::size_t> goal;  // the goal refused, as the caller numbered them; none: the mission as a whole
  // For people: with `goal`, what is wrong with it, to follow the caller's name for it ("is outside the map");
  // without, a whole sentence.
  std::string detail;
};

struct GoalCheckInputs {
  const Costmap* costmap = nullptr;  // the map in use's, with its zones
  const Building* building = nullptr;
  std::string map;  // the map in use's name
  // Another floor's map by its name (the map library's); null if it cannot be had.
  std::function<std::shared_ptr<const OccupancyGrid>(const std::string& map)> grid_of;
  bool lift_controller = false;  // the building's lift controller is configured
};

// The goals to drive (through lifts where they are on other floors), or why not.
using GoalCheckResult = std::variant<std::vector<MissionGoal>, MissionRefusal>;

// Undocking goals are not checked (they start on the dock, which the costmap may show as an obstacle).
GoalCheckResult CheckMissionGoals(std::vector<MissionGoal> goals, const GoalCheckInputs& inputs);

}  // namespace corridor::nav
