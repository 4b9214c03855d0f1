#include "nav/ground/laser_lanes.h"

#include <cmath>
#include <stdexcept>

namespace corridor::nav {

LaserLanes::LaserLanes(const MorpOptions& options, double height_m) : options_(options), height_m_(height_m) {
  if (!(options.span_m > 0.0) || !(options.lane_width_m > 0.0) || !(options.max_range_m > 0.0)) {
    throw std::invalid_argument("LaserLanes: widths and max_range_m must be positive");
  }
  offsets_ = LaneOffsets(options);
  results_.resize(offsets_.size());
}

const std::vector<LaneResult>& LaserLanes::Process(std::span<const Eigen::Vector2f> hits) {
  for (std::size_t j = 0; j < offsets_.size(); ++j) {
    results_[j] = LaneResult{};
    results_[j].offset_m = offsets_[j];
    results_[j].free_distance_m = options_.max_range_m;
  }
  for (const Eigen::Vector2f& hit : hits) {
    const double x = hit.x();
    if (!(x > 0.0) || x >= options_.max_range_m) continue;  // behind the robot's centre, or past the lanes
    const int j = LaneOnLine(options_, lane_count(), hit.y());
    if (j < 0) continue;
    LaneResult& lane = results_[static_cast<std::size_t>(j)];
    if (x < lane.free_distance_m) {
      lane.free_distance_m = x;
      lane.dead_end = true;
      lane.point = {x, hit.y(), height_m_};
    }
  }
  return results_;
}

}  // namespace corridor::nav
