// What the global planner plans on: the occupancy grid with keep-out zones (and, by policy, unknown space) as
// obstacles, their fast-marching distance field, robot-radius inflation, the distance cost d(n) of DPoom
// (Kim et al., IEEE Access 2022, section III-C), and the speed limit of speed zones per cell.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "nav/map/occupancy_grid.h"
#include "nav/map/zones.h"
#include "nav/planner/distance_field.h"

namespace corridor::nav {

enum class UnknownPolicy { kObstacle, kFree };

struct CostmapOptions {
  double robot_radius_m = 0.2;  // cells closer to an obstacle than this (plus the cell's own extent) are
                                // not traversable
  // d(n) at the inflation boundary, per metre travelled; 0 gives plain A*. With 1.5 and 0.5 m, Willow Garage paths
  // keep 0.36-0.40 m from walls instead of 0.25 m for 6.5 % more length (docs/benchmarks.md).
  double distance_weight = 1.5;
  double saturation_m = 0.5;    // clearance beyond the inflation boundary at which d(n) reaches 0
  int occupied_threshold = 65;  // cells at or above this occupancy are obstacles
  UnknownPolicy unknown = UnknownPolicy::kObstacle;
  // What only the obstacle layer shows (the camera saw it, the map does not) the local guard keeps its margin from
  // (ObstacleMemoryOptions::margin_m), more than the map's walls: a path within robot_radius_m + layer_margin_m of it
  // leads to a gap the robot will not drive through. Such cells add layer_cost to the step factor: a cost, not a wall,
  // so that a goal beside such an obstacle, and a gap that is the only way, are still planned.
  double layer_margin_m = 0.15;
  double layer_cost = 20.0;
};

class Costmap {
 public:
  static constexpr float kNoSpeedLimit = std::numeric_limits<float>::infinity();

  // Builds the costmap. Invalid zones must have been rejected before (see Validate).
  Costmap(const OccupancyGrid& grid, std::span<const Zone> zones, const CostmapOptions& options);
  // The same with every cell an obstacle layer marks occupied (kOccupiedCell; one value per cell of `grid`) made an
  // obstacle: what the map does not show (the 3D map's table tops, and whatever else the depth camera saw), with
  // layer_cost within layer_margin_m beyond the inflation around them. The map's own walls stay told apart from them
  // (WallWithin).
  Costmap(const OccupancyGrid& grid, std::span<const std::int8_t> layer, std::span<const Zone> zones,
          const CostmapOptions& options);

  const OccupancyGrid& grid() const { return grid_; }
  const CostmapOptions& options() const { return options_; }
  int width() const { return grid_.width(); }
  int height() const { return grid_.height(); }
  std::size_t Index(CellIndex c) const { return static_cast<std::size_t>(c.y) * grid_.width() + c.x; }

  bool IsObstacle(std::size_t i) const { return obstacle_[i] != 0; }
  bool InKeepOut(std::size_t i) const { return keep_out_[i] != 0; }
  bool Traversable(std::size_t i) const { return traversable_[i] != 0; }
  // Distance to the nearest obstacle cell, centre to centre, in metres (+infinity when farther than the march).
  float clearance_m(std::size_t i) const { return field_.distance_m[i]; }
  // The same at a map-frame point: +infinity outside the map (nothing known there to keep clear of).
  double ClearanceAt(const Eigen::Vector2d& p) const;
  // Whether a wall (a cell at or above occupied_threshold: not unknown space, nor a keep-out zone) lies within
  // radius_m of the map-frame point `p` (cell centres); `mapped_only`: a wall of the map itself, not one the obstacle
  // layer added.
  bool WallWithin(const Eigen::Vector2d& p, double radius_m, bool mapped_only = false) const;
  // The multiplier on step length: 1 + d(n).
  float step_factor(std::size_t i) const { return step_factor_[i]; }
  float speed_limit_mps(std::size_t i) const { return speed_limit_[i]; }

 private:
  OccupancyGrid grid_;
  CostmapOptions options_;
  std::vector<std::uint8_t> obstacle_;
  std::vector<std::uint8_t> keep_out_;
  std::vector<std::uint8_t> traversable_;
  DistanceField field_;
  std::vector<float> step_factor_;
  std::vector<float> speed_limit_;
  std::vector<std::uint8_t> layered_;  // per cell: a wall only through the obstacle layer (empty without a layer)
};

// The traversable cell with the most clearance within radius_m of `near` (a place to park or send the robot),
// or nullopt when none is traversable.
std::optional<Eigen::Vector2d> MostOpenCell(const Costmap& costmap, const Eigen::Vector2d& near, double radius_m);

}  // namespace corridor::nav
