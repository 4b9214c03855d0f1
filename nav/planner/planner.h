// The global planner's whole job for one request: search (astar.h), then turn the cell path into waypoints with
// headings and speed limits, and report length and clearance.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "nav/planner/astar.h"

namespace corridor::nav {

// Crossing the inflated band (a robot leaving it: AStar), the path's speed is capped at this.
inline constexpr double kBandSpeedMps = 0.15;

struct Waypoint {
  Pose2 pose;                                       // yaw: toward the next waypoint; the goal's yaw at the end
  double speed_limit_mps = Costmap::kNoSpeedLimit;  // the lowest speed zone on the way to this waypoint
};

struct Plan {
  std::vector<Waypoint> waypoints;     // start to goal, simplified
  std::vector<Eigen::Vector2d> dense;  // every cell centre of the search's path
  double length_m = 0.0;
  double min_clearance_m = 0.0;   // along the dense path: distance to the nearest obstacle cell
  double mean_clearance_m = 0.0;  // (centre to centre), capped at the costmap's march limit
  int expanded = 0;
};

struct PlanResult {
  PlanError error = PlanError::kNone;
  std::string detail;
  Plan plan;
  bool ok() const { return error == PlanError::kNone; }
};

struct PathOptions {
  double simplify_tolerance_m = 0.1;  // how far a simplified path may stray from the searched one
  std::span<const float> extra_cost;  // per cell, added to the step factor: see AStar
  bool robot_at_start = false;        // the robot stands at the start: see AStar
};

// Adds `cost` (a step-factor addition, see PathOptions::extra_cost) to every cell of `costmap` whose centre lies
// within radius_m of one of `points` (world frame; those off the map are skipped), into `extra`, which is sized to
// the costmap's cells (zeros) when empty. For obstacles the map does not show that the robot found in its way: a path
// planned with them goes round them where there is room, and still through them where there is not. Throws
// std::invalid_argument when `extra` has another size than the costmap's cells or `cost` is negative.
void AddPointCost(const Costmap& costmap, std::span<const Eigen::Vector2d> points, double radius_m, float cost,
                  std::vector<float>& extra);

// The extra step costs of one plan (PathOptions::extra_cost): where people walk (`traffic`, per cell; ignored unless
// it has one value per cell of `costmap`, as when made for another map) plus `cost` within radius_m of each of
// `blocking` (AddPointCost). Empty when there is neither.
std::vector<float> ExtraCosts(const Costmap& costmap, std::span<const float> traffic,
                              std::span<const Eigen::Vector2d> blocking, double radius_m, float cost);

// Plans from `start` to `goal`; when goal_yaw is set the last waypoint takes it. See AStar for `cancel`.
PlanResult PlanPath(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                    std::optional<double> goal_yaw = std::nullopt, const std::atomic<bool>* cancel = nullptr,
                    const PathOptions& options = {});

// True when a point of the polyline `candidate` within its first along_m metres lies farther than tolerance_m from
// the polyline `current`: a replanned path that goes another way, not the same way from a new start.
bool PathsDiverge(const std::vector<Eigen::Vector2d>& candidate, const std::vector<Eigen::Vector2d>& current,
                  double along_m, double tolerance_m);

// True when every cell the straight segment a-b passes is traversable.
bool SegmentTraversable(const Costmap& costmap, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// True when the rest of `path` for a robot at `from` is traversable: its legs from the waypoint nearest `from` on, but
// that within band_reach_m of `from` they may cross the inflated band (a robot's way out of it, as AStar plans it)
// and, under the robot's footprint, obstacle cells outside keep-out zones. For a path planned on an older map or
// zones: does it still stand? (band_reach_m 0: does it cross the band at all?)
bool RestOfPathTraversable(const Costmap& costmap, const std::vector<Waypoint>& path, const Eigen::Vector2d& from,
                           double band_reach_m = kEscapeReachM);

}  // namespace corridor::nav
