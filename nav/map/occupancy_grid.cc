#include "nav/map/occupancy_grid.h"

#include <cmath>
#include <stdexcept>

namespace corridor::nav {

OccupancyGrid::OccupancyGrid(int width, int height, double resolution_m, Pose2 origin, std::int8_t fill)
    : width_(width), height_(height), resolution_m_(resolution_m), origin_(origin) {
  if (width < 0 || height < 0 || !(resolution_m > 0.0)) {
    throw std::invalid_argument("OccupancyGrid: width and height must be >= 0 and resolution > 0");
  }
  cells_.assign(static_cast<std::size_t>(width) * height, fill);
}

std::optional<CellIndex> OccupancyGrid::WorldToCell(const Eigen::Vector2d& point_m) const {
  const Eigen::Vector2d local = origin_.Inverse().Transform(point_m) / resolution_m_;
  // Off the map (or not a number) before the cast: a far-away point would overflow int (found by fuzz_bodies).
  if (!(local.x() >= 0.0 && local.y() >= 0.0 && local.x() < width_ && local.y() < height_)) return std::nullopt;
  const CellIndex c{static_cast<int>(std::floor(local.x())), static_cast<int>(std::floor(local.y()))};
  if (!Contains(c)) return std::nullopt;
  return c;
}

Eigen::Vector2d OccupancyGrid::CellCenter(CellIndex c) const {
  return origin_.Transform(Eigen::Vector2d(c.x + 0.5, c.y + 0.5) * resolution_m_);
}

}  // namespace corridor::nav
