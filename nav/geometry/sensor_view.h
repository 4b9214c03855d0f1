// The floor a sensor covers from where it stands, when it does not see all round (a depth camera): a sector of
// half_angle_rad either side of the sensor's x axis, out to range_m.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct SensorView {
  Pose2 world_T_sensor;
  double half_angle_rad = 0.0;
  double range_m = 0.0;

  // A disc of `radius_m` around `p` (the sensor's parent frame) lies wholly inside.
  bool Covers(const Eigen::Vector2d& p, double radius_m) const {
    const Eigen::Vector2d local = world_T_sensor.Inverse().Transform(p);
    const double range = local.norm();
    if (range <= radius_m || range + radius_m > range_m) return false;  // around the sensor itself, or too far
    // The disc's angular half-width seen from the sensor, on top of its bearing.
    return std::abs(std::atan2(local.y(), local.x())) + std::asin(radius_m / range) <= half_angle_rad;
  }
};

}  // namespace corridor::nav
