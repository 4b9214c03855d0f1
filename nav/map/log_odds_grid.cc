#include "nav/map/log_odds_grid.h"

#include <algorithm>
#include <cmath>

#include "nav/map/grid_ray.h"

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
  const Pose2 grid_T_map = geometry_.origin().Inverse();
  const Eigen::Vector2d a = grid_T_map.Transform(from) / geometry_.resolution_m();
  const Eigen::Vector2d b = grid_T_map.Transform(to) / geometry_.resolution_m();
  const CellIndex last = ForEachCellBefore(a, b, [this](CellIndex cell) { Update(cell, false); });
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
