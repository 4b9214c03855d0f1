// A constructed world for the localization tests: an asymmetric room of line walls, and an exact laser scan of it.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/localization/range_scan.h"

namespace corridor::nav::testworld {

struct Wall {
  Eigen::Vector2d a;
  Eigen::Vector2d b;
};

// A 10 x 7 m room (x from -4 to 6, y from -3 to 4) with an inner wall, a pillar and an alcove, so that no two poses
// see the same scan.
inline const std::vector<Wall>& Room() {
  static const std::vector<Wall> walls = {
      {{-4, -3}, {6, -3}},      {{6, -3}, {6, 4}},          {{6, 4}, {-4, 4}},
      {{-4, 4}, {-4, -3}},      {{1.5, -3}, {1.5, -1.0}},  // inner wall from the south side
      {{4.0, 2.0}, {4.5, 2.0}}, {{4.5, 2.0}, {4.5, 2.5}},   {{4.5, 2.5}, {4.0, 2.5}},
      {{4.0, 2.5}, {4.0, 2.0}},                              // pillar
      {{-4, 1.0}, {-3.0, 1.0}}, {{-3.0, 1.0}, {-3.0, 2.5}},  // alcove
  };
  return walls;
}

// The range along a ray from `origin` in direction `d` to the nearest wall, or +infinity.
inline double Cast(const std::vector<Wall>& walls, const Eigen::Vector2d& origin, const Eigen::Vector2d& d) {
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : walls) {
    const Eigen::Vector2d e = w.b - w.a;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-12) continue;
    const Eigen::Vector2d f = w.a - origin;
    const double t = (f.x() * e.y() - f.y() * e.x()) / denom;
    const double u = (f.x() * d.y() - f.y() * d.x()) / denom;
    if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

// A 360-beam, 1-degree laser at the robot's centre, robot at `pose`.
inline RangeScan ScanAt(const std::vector<Wall>& walls, const Pose2& pose, int beams = 360,
                        double fov_rad = 2.0 * std::numbers::pi) {
  std::vector<float> ranges(beams);
  const double increment = fov_rad / beams;
  const double start = -fov_rad / 2.0;
  for (int i = 0; i < beams; ++i) {
    const double a = pose.yaw_rad + start + i * increment;
    ranges[i] = static_cast<float>(Cast(walls, pose.translation(), {std::cos(a), std::sin(a)}));
  }
  return ScanFromRanges(Pose2{}, start, increment, ranges, RangeLimits{});
}

}  // namespace corridor::nav::testworld
