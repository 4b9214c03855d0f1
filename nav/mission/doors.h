// Doors on a floor's map: lines across passages that the building's door controller opens. A mission asks for each
// door on its path to open before the robot reaches it (request_m ahead along the path), holds the robot short of
// the door's line (hold_m) until the controller says it is open, and releases it once the robot is through
// (release_m past it); a refusal, or no open door within timeout_s of asking, ends the mission with the reason. Doors
// still asked for when a mission ends (or its new path no longer crosses them) are released.
//
// Pure logic: the mission runner feeds it the path and what the controller reports, and passes on what it asks.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct Door {
  std::string id;
  Eigen::Vector2d a = Eigen::Vector2d::Zero();  // the line across the passage, map frame
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
};

struct DoorOptions {
  double request_m = 5.0;  // ask for a door this far ahead along the path
  // Until it is open, stop with the robot's centre this far before its line: beyond where the local policy would
  // start steering round the closed panel (MORP-RB's clear_distance_m from the robot's front).
  double hold_m = 1.6;
  double release_m = 0.8;   // release it once the robot's centre is this far past its line
  double timeout_s = 30.0;  // from asking until it is open
};
// Throws std::invalid_argument for options that do not make sense (hold beyond request, negative distances).
void Validate(const DoorOptions& options);

// What the door controller says of a door.
enum class DoorStatus { kClosed, kOpening, kOpen, kRefused, kFailed };
const char* ToString(DoorStatus status);
struct DoorReport {
  DoorStatus status = DoorStatus::kClosed;
  std::string detail;  // why, for a refusal or failure
};
using DoorReports = std::map<std::string, DoorReport>;

// Where a path crosses a door: the path's length from the crossing to its end.
struct DoorCrossing {
  std::string door;
  double from_end_m = 0.0;
};
// The doors `path` (a polyline) crosses, in order along it.
std::vector<DoorCrossing> DoorsOnPath(const std::vector<Eigen::Vector2d>& path, const std::vector<Door>& doors);

// What the robot's sensors mapped on a door's line (the closed panel) is not an obstacle to plan round: the door is
// the controller's business. Clears `layer` (one value per cell of `grid`, as the planner's obstacle layer) within
// half_width_m of each door's line.
void ClearDoors(const OccupancyGrid& grid, const std::vector<Door>& doors, double half_width_m,
                std::vector<std::int8_t>& layer);

// A request to the door controller.
struct DoorRequest {
  std::string door;
  bool open = true;  // false: release it
};

class DoorKeeper {
 public:
  explicit DoorKeeper(const DoorOptions& options) : options_(options) {}

  // The current leg's path crosses these doors; doors asked for that it no longer crosses are released.
  void SetPath(std::vector<DoorCrossing> crossings, std::vector<DoorRequest>& requests);

  struct Step {
    bool hold = false;                   // stop short of the next door: it is not open yet
    std::string waiting_for;             // the door held for
    std::optional<std::string> failure;  // end the mission: why
  };
  // `remaining_m`: the leg's path length still to drive.
  Step Update(double now_s, double remaining_m, const DoorReports& reports, std::vector<DoorRequest>& requests);
  // The mission ended: every door asked for is released.
  void ReleaseAll(std::vector<DoorRequest>& requests);

 private:
  DoorOptions options_;
  std::vector<DoorCrossing> crossings_;  // not yet passed, in order
  std::map<std::string, double> asked_;  // door -> when it was asked to open
};

}  // namespace corridor::nav
