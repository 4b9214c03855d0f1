#include "nav/tracking/traffic_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace corridor::nav {

TrafficMap::TrafficMap(const OccupancyGrid& geometry, const TrafficOptions& options)
    : geometry_(geometry.width(), geometry.height(), geometry.resolution_m(), geometry.origin(), kFreeCell),
      options_(options) {
  if (!(options.lane_half_width_m >= 0.0) || !(options.weight >= 0.0) || !(options.memory_s > 0.0)) {
    throw std::invalid_argument("traffic: need lane_half_width_m >= 0, weight >= 0 and memory_s > 0");
  }
  reach_cells_ = static_cast<int>(std::ceil(options.lane_half_width_m / geometry.resolution_m()));
  Clear();
}

void TrafficMap::Clear() {
  last_walked_s_.assign(static_cast<std::size_t>(geometry_.width()) * static_cast<std::size_t>(geometry_.height()),
                        -std::numeric_limits<double>::infinity());
  last_any_s_ = -std::numeric_limits<double>::infinity();
}

void TrafficMap::Add(double stamp_s, const std::vector<TrackedObject>& objects) {
  const double reach2 = options_.lane_half_width_m * options_.lane_half_width_m;
  for (const TrackedObject& o : objects) {
    if (!o.moving) continue;
    const auto centre = geometry_.WorldToCell(o.position);
    if (!centre) continue;
    for (int dy = -reach_cells_; dy <= reach_cells_; ++dy) {
      for (int dx = -reach_cells_; dx <= reach_cells_; ++dx) {
        const CellIndex c{centre->x + dx, centre->y + dy};
        if (!geometry_.Contains(c) || (geometry_.CellCenter(c) - o.position).squaredNorm() > reach2) continue;
        double& last = last_walked_s_[static_cast<std::size_t>(c.y) * geometry_.width() + c.x];
        last = std::max(last, stamp_s);
        last_any_s_ = std::max(last_any_s_, stamp_s);
      }
    }
  }
}

std::vector<float> TrafficMap::StepCost(double stamp_s) const {
  std::vector<float> cost(last_walked_s_.size(), 0.0f);
  for (std::size_t i = 0; i < cost.size(); ++i) {
    const double age = stamp_s - last_walked_s_[i];
    if (age < kFadedAfter * options_.memory_s) {
      cost[i] = static_cast<float>(options_.weight * std::exp(-std::max(0.0, age) / options_.memory_s));
    }
  }
  return cost;
}

}  // namespace corridor::nav
