// A pinhole depth camera mounted on the robot: intrinsics in pixels and its pose in the base frame (x forward, y left,
// z up, origin on the floor under the robot's centre). The optical frame is x right, y down, z forward.
#pragma once

#include <Eigen/Geometry>

namespace corridor::nav {

struct PinholeCamera {
  int width = 0;
  int height = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();

  // The ray through pixel (u, v) in the optical frame, scaled so that its z is 1: depth times it is the point.
  Eigen::Vector3d Ray(double u, double v) const { return {(u - cx) / fx, (v - cy) / fy, 1.0}; }
  // Projects a base-frame point; false when it is behind the camera.
  bool Project(const Eigen::Vector3d& point_base, Eigen::Vector2d& pixel) const {
    const Eigen::Vector3d p = base_T_camera.inverse() * point_base;
    if (p.z() <= 1e-9) return false;
    pixel = {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
    return true;
  }
};

}  // namespace corridor::nav
