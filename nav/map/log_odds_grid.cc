#include "nav/map/log_odds_grid.h"

#include <algorithm>
#include <cmath>

namespace corridor::nav {
namespace {

double LogOdds(double p) { return std::log(p / (1.0 - p)); }

}  // namespace

LogOddsGrid::LogOddsGrid(int width, int height, double resolution_m, Pose2 origin, const LogOddsOptions& options)
    : geometry_(width, height, resolution_m, origin, kUnknownCell),
      options_(options),
      l_hit_(LogOdds(options.p_hit)),
      l_miss_(LogOdds(options.p_miss)),
      log_odds_(static_cast<std::size_t>(width) * height, 0.0f),
      observed_(static_cast<std::size_t>(width) * height, 0) {}

void LogOddsGrid::Update(CellIndex cell, bool hit) {
  if (!geometry_.Contains(cell)) return;
  float& l = log_odds_[Index(cell)];
  l = static_cast<float>(std::clamp(l + (hit ? l_hit_ : l_miss_), options_.clamp_min, options_.clamp_max));
  observed_[Index(cell)] = 1;
}

void LogOddsGrid::IntegrateRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool hit) {
  // Walk the cells the segment crosses (Amanatides and Woo's traversal), in grid units.
  const Pose2 grid_T_map = geometry_.origin().Inverse();
  const Eigen::Vector2d a = grid_T_map.Transform(from) / geometry_.resolution_m();
  const Eigen::Vector2d b = grid_T_map.Transform(to) / geometry_.resolution_m();
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
    Update(cell, false);
    if (next_x < next_y) {
      cell.x += step_x;
      next_x += delta_x;
    } else {
      cell.y += step_y;
      next_y += delta_y;
    }
  }
  Update(last, hit);
}

double LogOddsGrid::Probability(CellIndex cell) const {
  const double l = log_odds_[Index(cell)];
  return 1.0 - 1.0 / (1.0 + std::exp(l));
}

OccupancyGrid LogOddsGrid::ToOccupancyGrid() const {
  OccupancyGrid out = geometry_;
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      const CellIndex c{x, y};
      if (!observed_[Index(c)]) continue;
      const double p = Probability(c);
      out.at(c) = p > options_.occupied_above ? kOccupiedCell : p < options_.free_below ? kFreeCell : kUnknownCell;
    }
  }
  return out;
}

}  // namespace corridor::nav
