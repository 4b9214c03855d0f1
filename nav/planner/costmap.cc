#include "nav/planner/costmap.h"

#include <algorithm>
#include <cmath>

namespace corridor::nav {
namespace {

// A cell's centre must be this many cells farther than the robot radius from an obstacle cell's centre: the
// obstacle cell's nearest point can be up to half a diagonal (0.71 cells) closer than its centre.
constexpr double kCellExtent = 0.71;

// How far a traversable cell's centre is from every obstacle cell's centre.
double InflationM(const CostmapOptions& options, double resolution_m) {
  return options.robot_radius_m + kCellExtent * resolution_m;
}

OccupancyGrid WithObstacleLayer(const OccupancyGrid& grid, std::span<const std::int8_t> layer) {
  OccupancyGrid merged = grid;
  std::vector<std::int8_t>& cells = merged.mutable_cells();
  const std::size_t n = std::min(cells.size(), layer.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (layer[i] == kOccupiedCell) cells[i] = kOccupiedCell;
  }
  return merged;
}

// Per cell of a width x height mask: whether its centre lies nearer than radius_cells to the centre of a marked cell.
// A disc is stamped round each marked cell on the mask's edge only (the nearest marked cell to anything outside is
// one), which costs a fraction of a fast march over the mask.
std::vector<std::uint8_t> Within(const std::vector<std::uint8_t>& marked, int w, int h, double radius_cells) {
  const int reach = static_cast<int>(std::ceil(radius_cells));
  std::vector<std::pair<int, int>> disc;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy < radius_cells * radius_cells) disc.emplace_back(dx, dy);
    }
  }
  const auto on_edge = [&](int x, int y, std::size_t i) {
    return x == 0 || y == 0 || x == w - 1 || y == h - 1 || !marked[i - 1] || !marked[i + 1] || !marked[i - w] ||
           !marked[i + w];
  };
  std::vector<std::uint8_t> within(marked.size(), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (!marked[i] || !on_edge(x, y, i)) continue;
      for (const auto& [dx, dy] : disc) {
        const int nx = x + dx;
        const int ny = y + dy;
        if (nx >= 0 && nx < w && ny >= 0 && ny < h) within[static_cast<std::size_t>(ny) * w + nx] = 1;
      }
    }
  }
  return within;
}

}  // namespace

Costmap::Costmap(const OccupancyGrid& grid, std::span<const Zone> zones, const CostmapOptions& options)
    : grid_(grid), options_(options) {
  const std::size_t n = grid.cells().size();
  obstacle_.assign(n, 0);
  keep_out_.assign(n, 0);
  for (const Zone& z : zones) {
    if (z.kind == ZoneKind::kKeepOut) Rasterize(z.polygon, grid, keep_out_, 1);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::int8_t v = grid.cells()[i];
    const bool unknown_blocks = v == kUnknownCell && options.unknown == UnknownPolicy::kObstacle;
    obstacle_[i] = keep_out_[i] || unknown_blocks || v >= options.occupied_threshold;
  }

  const double inflation_m = InflationM(options, grid.resolution_m());
  field_ = FastMarchingDistance(obstacle_, grid.width(), grid.height(), grid.resolution_m(),
                                {.max_distance_m = inflation_m + options.saturation_m + grid.resolution_m()});
  traversable_.assign(n, 0);
  step_factor_.assign(n, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const double clearance = field_.distance_m[i];
    traversable_[i] = !obstacle_[i] && clearance >= inflation_m;
    // d(n): the FMM distance reversed, from distance_weight at the inflation boundary to 0 at saturation.
    const double beyond = clearance - inflation_m;
    if (traversable_[i] && beyond < options.saturation_m) {
      step_factor_[i] = static_cast<float>(1.0 + options.distance_weight * (1.0 - beyond / options.saturation_m));
    }
  }

  speed_limit_.assign(n, kNoSpeedLimit);
  std::vector<std::uint8_t> mask(n);
  for (const Zone& z : zones) {
    if (z.kind != ZoneKind::kSpeedLimit) continue;
    std::fill(mask.begin(), mask.end(), 0);
    Rasterize(z.polygon, grid, mask, 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (mask[i]) speed_limit_[i] = std::min(speed_limit_[i], static_cast<float>(z.max_speed_mps));
    }
  }
}

Costmap::Costmap(const OccupancyGrid& grid, std::span<const std::int8_t> layer, std::span<const Zone> zones,
                 const CostmapOptions& options)
    : Costmap(WithObstacleLayer(grid, layer), zones, options) {
  const std::size_t n = std::min(grid.cells().size(), layer.size());
  layered_.assign(grid.cells().size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    layered_[i] = layer[i] == kOccupiedCell && grid.cells()[i] < options.occupied_threshold;
  }
  if (options.layer_margin_m <= 0.0 || options.layer_cost <= 0.0) return;
  const double kept_m = InflationM(options, grid.resolution_m()) + options.layer_margin_m;
  const std::vector<std::uint8_t> within = Within(layered_, grid.width(), grid.height(), kept_m / grid.resolution_m());
  for (std::size_t i = 0; i < within.size(); ++i) {
    if (within[i] && traversable_[i]) step_factor_[i] += static_cast<float>(options.layer_cost);
  }
}

double Costmap::ClearanceAt(const Eigen::Vector2d& p) const {
  const auto cell = grid_.WorldToCell(p);
  return cell ? clearance_m(Index(*cell)) : std::numeric_limits<double>::infinity();
}

bool Costmap::WallWithin(const Eigen::Vector2d& p, double radius_m, bool mapped_only) const {
  const double res = grid_.resolution_m();
  const Eigen::Vector2d local = grid_.origin().Inverse().Transform(p) / res;
  const int reach = static_cast<int>(std::ceil(radius_m / res)) + 1;
  const int cx = static_cast<int>(std::floor(local.x()));
  const int cy = static_cast<int>(std::floor(local.y()));
  for (int y = cy - reach; y <= cy + reach; ++y) {
    for (int x = cx - reach; x <= cx + reach; ++x) {
      const CellIndex c{x, y};
      if (!grid_.Contains(c) || grid_.at(c) < options_.occupied_threshold) continue;
      if (mapped_only && !layered_.empty() && layered_[Index(c)]) continue;
      if ((grid_.CellCenter(c) - p).squaredNorm() <= radius_m * radius_m) return true;
    }
  }
  return false;
}

std::optional<Eigen::Vector2d> MostOpenCell(const Costmap& costmap, const Eigen::Vector2d& near, double radius_m) {
  const OccupancyGrid& grid = costmap.grid();
  const Eigen::Vector2d local = grid.origin().Inverse().Transform(near) / grid.resolution_m();
  const int cx = static_cast<int>(std::floor(local.x()));
  const int cy = static_cast<int>(std::floor(local.y()));
  const int reach = static_cast<int>(std::ceil(radius_m / grid.resolution_m()));
  std::optional<Eigen::Vector2d> best;
  float best_clearance = -1.0f;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const CellIndex c{cx + dx, cy + dy};
      if (!grid.Contains(c) || (grid.CellCenter(c) - near).norm() > radius_m) continue;
      const std::size_t i = costmap.Index(c);
      if (!costmap.Traversable(i) || costmap.clearance_m(i) <= best_clearance) continue;
      best_clearance = costmap.clearance_m(i);
      best = grid.CellCenter(c);
    }
  }
  return best;
}

}  // namespace corridor::nav
