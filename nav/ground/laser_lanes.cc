#include "nav/ground/laser_lanes.h"

#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

// A lane takes the hits within this fraction of the lanes' spacing of its centre line: MORP samples a line along
// each lane, not a band, so a wall running beside the robot at the edge of the lanes it steers on is no dead-end
// ahead (a band would stop the robot in every corridor of its width plus the gate's margin).
constexpr double kLineHalfWidth = 0.25;

}  // namespace

LaserLanes::LaserLanes(const MorpOptions& options, double height_m) : options_(options), height_m_(height_m) {
  if (!(options.span_m > 0.0) || !(options.lane_width_m > 0.0) || !(options.max_range_m > 0.0)) {
    throw std::invalid_argument("LaserLanes: widths and max_range_m must be positive");
  }
  offsets_ = LaneOffsets(options);
  lane_m_ = options.span_m / static_cast<double>(offsets_.size());
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
    // Lanes run left (+y) to right, lane_m_ apart: the nearest lane's line, if the hit lies on it.
    const double from_first = (offsets_.front() - hit.y()) / lane_m_;
    const long j = std::lround(from_first);
    if (j < 0 || j >= static_cast<long>(results_.size())) continue;
    if (std::abs(from_first - static_cast<double>(j)) * lane_m_ > kLineHalfWidth * lane_m_) continue;
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
