// The floor a sensor covers from where it stands, when it does not see all round (a depth camera): a sector of
// half_angle_rad either side of the sensor's x axis, out to range_m, less a stereo pair's shadow.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct SensorView {
  SensorView() = default;
  SensorView(const Pose2& pose, double half_angle, double range, const StereoShadow& stereo = {}, double fx = 0.0,
             double cx = 0.0)
      : world_T_sensor(pose), half_angle_rad(half_angle), range_m(range), shadow(stereo), fx_px(fx), cx_px(cx) {}

  Pose2 world_T_sensor;
  double half_angle_rad = 0.0;
  double range_m = 0.0;
  // A stereo pair's shadow, for a camera looking along the view's x axis with these horizontal intrinsics: what lies
  // close by on its left is not seen (PinholeCamera::stereo). None for other sensors.
  StereoShadow shadow;
  double fx_px = 0.0;
  double cx_px = 0.0;

  // A disc of `radius_m` around `p` (the sensor's parent frame) lies wholly inside.
  bool Covers(const Eigen::Vector2d& p, double radius_m) const {
    const Eigen::Vector2d local = world_T_sensor.Inverse().Transform(p);
    const double range = local.norm();
    if (range <= radius_m || range + radius_m > range_m) return false;  // around the sensor itself, or too far
    // The disc's angular half-width seen from the sensor, on top of its bearing.
    if (std::abs(std::atan2(local.y(), local.x())) + std::asin(radius_m / range) > half_angle_rad) return false;
    if (shadow.focal_baseline_px_m <= 0.0) return true;
    // Its leftmost side at its nearest depth, in the image's column u = cx - fx y / x.
    const double depth = local.x() - radius_m;
    return depth > 0.0 && shadow.Sees(cx_px - fx_px * (local.y() + radius_m) / depth, depth);
  }
};

}  // namespace corridor::nav
