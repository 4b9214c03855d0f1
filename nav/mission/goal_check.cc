#include "nav/mission/goal_check.h"

#include <algorithm>
#include <stdexcept>

namespace corridor::nav {

const char* ToString(GoalRefusal refusal) {
  switch (refusal) {
    case GoalRefusal::kOutsideMap: return "goal_outside_map";
    case GoalRefusal::kOccupied: return "goal_occupied";
    case GoalRefusal::kInKeepOut: return "goal_in_keep_out";
    case GoalRefusal::kUnknownFloor: return "unknown_floor";
    case GoalRefusal::kNotOnFloor: return "no_floor";
    case GoalRefusal::kNoLiftController: return "no_lift";
    case GoalRefusal::kNoLiftRoute: return "no_lift_route";
  }
  return "refused";
}

std::string Describe(const MissionRefusal& refusal, const std::string& goal_name) {
  return refusal.goal ? goal_name + " " + refusal.detail : refusal.detail;
}

GoalCheckResult CheckMissionGoals(std::vector<MissionGoal> goals, const GoalCheckInputs& in) {
  const Floor* here = in.building != nullptr ? in.building->FloorOfMap(in.map) : nullptr;
  const auto refuse = [](GoalRefusal reason, std::optional<std::size_t> goal, std::string detail) {
    return MissionRefusal{reason, goal, std::move(detail)};
  };
  for (std::size_t i = 0; i < goals.size(); ++i) {
    const MissionGoal& g = goals[i];
    if (g.action == GoalAction::kUndock) continue;
    if (!g.floor.empty() && (here == nullptr || g.floor != here->name)) {
      // On another floor: its map must show the goal free (its costmap is made when the robot arrives there).
      const Floor* floor = in.building != nullptr ? in.building->FloorNamed(g.floor) : nullptr;
      if (floor == nullptr) {
        return refuse(GoalRefusal::kUnknownFloor, i, "is on floor '" + g.floor + "', which the building has not");
      }
      const std::shared_ptr<const OccupancyGrid> grid = in.grid_of ? in.grid_of(floor->map) : nullptr;
      const auto cell = grid ? grid->WorldToCell(g.pose.translation()) : std::nullopt;
      if (!cell) return refuse(GoalRefusal::kOutsideMap, i, "is outside floor " + g.floor + "'s map");
      if (grid->at(*cell) != kFreeCell) {
        return refuse(GoalRefusal::kOccupied, i, "is not free on floor " + g.floor + "'s map");
      }
      continue;
    }
    const auto cell = in.costmap->grid().WorldToCell(g.pose.translation());
    if (!cell) return refuse(GoalRefusal::kOutsideMap, i, "is outside the map");
    const std::size_t index = in.costmap->Index(*cell);
    if (!in.costmap->Traversable(index)) {
      if (in.costmap->InKeepOut(index)) return refuse(GoalRefusal::kInKeepOut, i, "is in a keep-out zone");
      return refuse(GoalRefusal::kOccupied, i, "is occupied or too close to an obstacle");
    }
  }
  if (std::none_of(goals.begin(), goals.end(), [](const MissionGoal& g) { return !g.floor.empty(); })) return goals;
  // Goals on floors: through the building's lifts.
  if (here == nullptr) {
    return refuse(GoalRefusal::kNotOnFloor, std::nullopt,
                  "the map in use, '" + in.map + "', is no floor of the building");
  }
  if (!in.lift_controller && std::any_of(goals.begin(), goals.end(), [&](const MissionGoal& g) {
        return !g.floor.empty() && g.floor != here->name;
      })) {
    return refuse(GoalRefusal::kNoLiftController, std::nullopt,
                  "goals on other floors need the building's lift controller (building.controller)");
  }
  try {
    return ThroughLifts(*in.building, here->name, std::move(goals));
  } catch (const std::invalid_argument& e) {
    return refuse(GoalRefusal::kNoLiftRoute, std::nullopt, e.what());
  }
}

}  // namespace corridor::nav
