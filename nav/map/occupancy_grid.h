// A 2D occupancy grid in the ROS convention: cell (0, 0) is the lower-left cell, whose lower-left corner
// sits at `origin` in the map frame; x grows along columns, y along rows.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

// Cell values follow nav_msgs/OccupancyGrid: -1 unknown, 0 free ... 100 occupied.
inline constexpr std::int8_t kUnknownCell = -1;
inline constexpr std::int8_t kFreeCell = 0;
inline constexpr std::int8_t kOccupiedCell = 100;

struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex&) const = default;
};

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  // A grid of `width` x `height` cells, all set to `fill`. Requires width, height >= 0 and resolution > 0.
  OccupancyGrid(int width, int height, double resolution_m, Pose2 origin, std::int8_t fill = kUnknownCell);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Pose2& origin() const { return origin_; }
  const std::vector<std::int8_t>& cells() const { return cells_; }
  std::vector<std::int8_t>& mutable_cells() { return cells_; }

  bool Contains(CellIndex c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  // The cell value; requires Contains(c).
  std::int8_t at(CellIndex c) const { return cells_[Index(c)]; }
  std::int8_t& at(CellIndex c) { return cells_[Index(c)]; }

  // The cell that holds a map-frame point, or nullopt when the point is outside the grid.
  std::optional<CellIndex> WorldToCell(const Eigen::Vector2d& point_m) const;
  // The map-frame centre of a cell (defined for any index, inside the grid or not).
  Eigen::Vector2d CellCenter(CellIndex c) const;

 private:
  std::size_t Index(CellIndex c) const { return static_cast<std::size_t>(c.y) * width_ + c.x; }

  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  Pose2 origin_;
  std::vector<std::int8_t> cells_;
};

}  // namespace corridor::nav
