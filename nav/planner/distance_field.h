// Distance from obstacles by the fast marching method: the viscosity solution of the Eikonal equation |grad T| = 1
// with T = 0 on obstacle cells, on the grid (Sethian, "A fast marching level set method for monotonically advancing
// fronts", PNAS 1996). The planner's distance cost (DPoom, Kim et al., IEEE Access 2022, section III-C) and its
// robot-radius inflation both read this field.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace corridor::nav {

// A row-major field of distances in metres; +infinity where no obstacle is within the march limit.
struct DistanceField {
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  std::vector<float> distance_m;

  float at(int x, int y) const { return distance_m[static_cast<std::size_t>(y) * width + x]; }
};

struct FastMarchingOptions {
  // Marching stops once the front passes this distance; farther cells get +infinity. Everything the planner
  // uses (inflation, distance cost) saturates well before it, so this bounds the work, not the answer.
  double max_distance_m = std::numeric_limits<double>::infinity();
};

// `obstacle` is row-major, width x height, non-zero for obstacle cells. Second-order upwind differences are used
// where two upwind neighbours are known along an axis (Sethian's "higher accuracy" scheme), first-order otherwise.
DistanceField FastMarchingDistance(const std::vector<std::uint8_t>& obstacle, int width, int height,
                                   double resolution_m, const FastMarchingOptions& options = {});

}  // namespace corridor::nav
