// What the local policies' tests drive on: ten free lanes and a straight path.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "nav/ground/morp.h"
#include "nav/planner/planner.h"

namespace corridor::testing {

using nav::LaneResult;
using nav::Pose2;
using nav::Waypoint;

// Ten lanes from left to right (corridor's MORP over 1 m), all free 4 m but `blocked` (index: distance).
inline std::vector<LaneResult> TenLanes(const std::vector<std::pair<int, double>>& blocked = {}) {
  std::vector<LaneResult> lanes(10);
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    lanes[i].offset_m = 0.45 - 0.1 * static_cast<double>(i);
    lanes[i].free_distance_m = 4.0;
  }
  for (const auto& [i, d] : blocked) {
    LaneResult& lane = lanes[static_cast<std::size_t>(i)];
    lane.dead_end = true;
    lane.free_distance_m = d;
    lane.point = {d, lane.offset_m, 0.0};
  }
  return lanes;
}

// A straight path 5 m east from the origin.
inline std::vector<Waypoint> FiveMetresEast() {
  std::vector<Waypoint> path;
  for (int i = 0; i <= 50; ++i) path.push_back(Waypoint{Pose2{0.1 * i, 0.0, 0.0}});
  return path;
}

}  // namespace corridor::testing
