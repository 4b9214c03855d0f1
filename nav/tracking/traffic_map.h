// Where people have been walking: a grid over the map remembering when a moving object last passed each cell, so
// that the global planner can keep the robot out of people's ways (AStar's extra_cost).
//
// People in a building keep to their ways: corridors, the line between two doors, the walk someone paces while on
// the phone. A robot at a third of their speed that plans straight through such a way spends its time evading the
// people on it; one that plans around the ends of their walks, or crosses them once rather than along, does not.
// This is a flow map in the simplest form (Kucner et al. call the general idea maps of dynamics): only "someone
// walked here recently", fading with time, no directions.
#pragma once

#include <vector>

#include "nav/map/occupancy_grid.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct TrafficOptions {
  double lane_half_width_m = 0.75;  // cells this near a walking person are on their way (their radius, the robot's
                                    // and a margin)
  double weight = 3.0;              // extra step cost (per metre, as the costmap's d(n)) of a cell just walked
  double memory_s = 30.0;           // the cost fades with this time constant
};

class TrafficMap {
 public:
  // A map over `geometry`'s cells (its contents are not used). Throws std::invalid_argument for bad options.
  TrafficMap(const OccupancyGrid& geometry, const TrafficOptions& options);

  // Marks the ways of the moving objects among `objects`, seen at stamp_s.
  void Add(double stamp_s, const std::vector<TrackedObject>& objects);

  // Per cell (row-major, as the geometry's cells), the extra step cost at stamp_s: for AStar's extra_cost.
  std::vector<float> StepCost(double stamp_s) const;
  // True when no cell has a cost at stamp_s: nobody has walked, or it has faded.
  bool Empty(double stamp_s) const { return stamp_s - last_any_s_ >= kFadedAfter * options_.memory_s; }

  void Clear();

 private:
  OccupancyGrid geometry_;  // cells unused: width, height, resolution and origin
  TrafficOptions options_;
  static constexpr double kFadedAfter = 10.0;  // memory_s: costs older than this are 0 (below 5e-5 of the weight)
  std::vector<double> last_walked_s_;          // -infinity: never
  double last_any_s_;                          // the newest of them
  int reach_cells_;
};

}  // namespace corridor::nav
