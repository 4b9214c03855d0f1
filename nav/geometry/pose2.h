// Planar poses for a ground robot: position in metres and heading in radians, in a named frame that the
// caller keeps track of (the map frame unless stated otherwise).
#pragma once

#include <Eigen/Geometry>

namespace corridor::nav {

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle_rad);

// A rigid transform in the plane. Composition follows the usual frame convention:
// a_T_c = a_T_b * b_T_c, and Transform(p) maps a point from the child frame into the parent frame.
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  Pose2 operator*(const Pose2& child) const;
  Pose2 Inverse() const;
  Eigen::Vector2d Transform(const Eigen::Vector2d& point) const;
  Eigen::Vector2d translation() const { return {x_m, y_m}; }
  // The 3D rigid transform of this pose at height 0 (z up).
  Eigen::Isometry3d ToIsometry3() const;
};

// A planar velocity in the robot frame: forward speed and turn rate (counter-clockwise positive).
struct Twist2 {
  double linear_mps = 0.0;
  double angular_rps = 0.0;
};

// The motion of driving `twist` for t_s seconds along the exact arc, in the frame the robot started in.
Pose2 Arc(const Twist2& twist, double t_s);
// The pose reached by driving `twist` from `start` for t_s seconds: start * Arc(twist, t_s).
Pose2 DriveArc(const Pose2& start, const Twist2& twist, double t_s);

// The pose a fraction f (0..1) of the way from a to b: the step between them, in a's frame, scaled by f.
Pose2 Interpolate(const Pose2& a, const Pose2& b, double f);

}  // namespace corridor::nav
