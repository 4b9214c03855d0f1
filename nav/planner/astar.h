// Global path search: 8-connected A* on a Costmap with f(n) = g(n) + h(n) + d(n) (DPoom, Kim et al., IEEE Access
// 2022, Algorithm 1). d(n) enters through each step's cost, length x (1 + d(n)), so the cost a path accumulates
// grows near obstacles and the search prefers paths that keep their distance; h is the octile distance, which is
// admissible because no step costs less than its length. With distance_weight 0 this is plain A* (f = g + h).
#pragma once

#include <atomic>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/planner/costmap.h"

namespace corridor::nav {

inline constexpr double kEscapeRadiusM = 0.5;
// A robot cut off from its goal by the inflated band may cross it this far from where it stands (AStar).
inline constexpr double kEscapeReachM = 3.0;

enum class PlanError {
  kNone,
  kStartOutsideMap,
  kStartOccupied,
  kGoalOutsideMap,
  kGoalOccupied,
  kNoPath,
  kCancelled,
};
const char* ToString(PlanError error);

struct GridPath {
  std::vector<CellIndex> cells;  // start to goal
  double cost = 0.0;             // accumulated g at the goal, metres weighted by 1 + d(n)
  int expanded = 0;              // nodes taken from the open list
};

struct SearchResult {
  PlanError error = PlanError::kNone;
  std::string detail;  // for people: what was wrong and where
  GridPath path;
};

// Searches from `start` to `goal` (map-frame metres). A start inside the inflated band around obstacles (a robot
// that drove close to a wall, or into a tight spot among a map's specks) may leave it along increasing clearance,
// and through any cell of the band within kEscapeRadiusM of it (the robot got there, so it can back out). With
// robot_at_start (the robot stands at `start`, as when a mission plans from its pose), obstacle and unknown cells
// under its footprint (robot_radius_m) are passable too: the map is wrong there, or the pose a little off; and when
// that finds no way (the robot on an island of free space among a map's unknown specks, cut off by their inflation, or
// deep in the band), a second search may cross the band and the unknown specks within 3 m of it, the robot's radius
// and a cell from every wall the map knows, at four (unknown: eight) times the cost (PlanPath has the robot crawl
// until it is across). Otherwise a start on an obstacle cell is refused, and a start in a keep-out zone always is.
// `cancel`, when non-null, is polled; setting it makes the search return kCancelled. Thread-compatible: one search
// per Costmap at a time is not required (the costmap is read-only). `extra_cost`, when not empty, holds one
// non-negative value per cell (costmap.Index) added to the cell's step factor: costs that change faster than the
// costmap is rebuilt, such as where people have been walking (nav/tracking/traffic_map.h). Its size must be the
// costmap's (std::invalid_argument otherwise).
SearchResult AStar(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                   const std::atomic<bool>* cancel = nullptr, std::span<const float> extra_cost = {},
                   bool robot_at_start = false);

}  // namespace corridor::nav
