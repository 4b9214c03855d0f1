#include "nav/geometry/pose2.h"

#include <cmath>
#include <numbers>

namespace corridor::nav {

double WrapAngle(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * std::numbers::pi);
  if (wrapped <= -std::numbers::pi) wrapped += 2.0 * std::numbers::pi;
  return wrapped;
}

Pose2 Pose2::operator*(const Pose2& child) const {
  const Eigen::Vector2d t = Transform(child.translation());
  return {t.x(), t.y(), WrapAngle(yaw_rad + child.yaw_rad)};
}

Pose2 Pose2::Inverse() const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {-c * x_m - s * y_m, s * x_m - c * y_m, WrapAngle(-yaw_rad)};
}

Eigen::Vector2d Pose2::Transform(const Eigen::Vector2d& point) const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {x_m + c * point.x() - s * point.y(), y_m + s * point.x() + c * point.y()};
}

Pose2 Arc(const Twist2& twist, double t_s) {
  const double v = twist.linear_mps;
  const double w = twist.angular_rps;
  const double dyaw = w * t_s;
  // Chord of the arc in the robot frame; the straight-line limit when the turn is negligible.
  const double forward = std::abs(dyaw) < 1e-9 ? v * t_s : v / w * std::sin(dyaw);
  const double left = std::abs(dyaw) < 1e-9 ? 0.0 : v / w * (1.0 - std::cos(dyaw));
  return {forward, left, dyaw};
}

Pose2 DriveArc(const Pose2& start, const Twist2& twist, double t_s) { return start * Arc(twist, t_s); }

Pose2 Interpolate(const Pose2& a, const Pose2& b, double f) {
  const Pose2 step = a.Inverse() * b;
  return a * Pose2{f * step.x_m, f * step.y_m, f * WrapAngle(step.yaw_rad)};
}

Eigen::Isometry3d Pose2::ToIsometry3() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x_m, y_m, 0.0);
  t.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

}  // namespace corridor::nav
