// The cells a straight segment crosses on a grid (Amanatides and Woo, "A fast voxel traversal algorithm for ray
// tracing", Eurographics 1987), for ray casting a range beam into an occupancy grid.
#pragma once

#include <cmath>
#include <cstdlib>
#include <limits>

#include <Eigen/Core>

#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

// Calls visit(CellIndex) for every cell the segment from `a` to `b` crosses, in order, except the cell holding `b`,
// which it returns. `a` and `b` are in grid units: cell (i, j) covers [i, i + 1) x [j, j + 1). Cells need not be
// inside any grid: the caller bounds them.
template <typename Visit>
CellIndex ForEachCellBefore(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Visit&& visit) {
  CellIndex cell{static_cast<int>(std::floor(a.x())), static_cast<int>(std::floor(a.y()))};
  const CellIndex last{static_cast<int>(std::floor(b.x())), static_cast<int>(std::floor(b.y()))};
  const Eigen::Vector2d d = b - a;
  const int step_x = d.x() > 0 ? 1 : -1;
  const int step_y = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double delta_x = d.x() != 0.0 ? std::abs(1.0 / d.x()) : inf;
  const double delta_y = d.y() != 0.0 ? std::abs(1.0 / d.y()) : inf;
  double next_x = d.x() != 0.0 ? ((step_x > 0 ? cell.x + 1 - a.x() : a.x() - cell.x) * delta_x) : inf;
  double next_y = d.y() != 0.0 ? ((step_y > 0 ? cell.y + 1 - a.y() : a.y() - cell.y) * delta_y) : inf;
  const int max_steps = std::abs(last.x - cell.x) + std::abs(last.y - cell.y);
  for (int i = 0; i < max_steps && !(cell == last); ++i) {
    visit(cell);
    if (next_x < next_y) {
      cell.x += step_x;
      next_x += delta_x;
    } else {
      cell.y += step_y;
      next_y += delta_y;
    }
  }
  return last;
}

}  // namespace corridor::nav
