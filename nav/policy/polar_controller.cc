#include "nav/policy/polar_controller.h"

#include <cmath>
#include <numbers>

namespace corridor::nav {

void ValidateGains(const PolarGains& g) {
  if (!(g.k_rho > 0.0)) throw std::invalid_argument("k_rho must be > 0");
  if (!(g.k_beta < 0.0)) throw std::invalid_argument("k_beta must be < 0");
  if (!(g.k_alpha - g.k_rho > 0.0)) throw std::invalid_argument("k_alpha - k_rho must be > 0");
}

PolarCommand PolarControl(const Pose2& robot, const Pose2& goal, const PolarGains& gains, bool allow_reverse) {
  const double dx = goal.x_m - robot.x_m;
  const double dy = goal.y_m - robot.y_m;
  const double bearing = std::atan2(dy, dx);
  PolarCommand out;
  out.rho = std::hypot(dx, dy);
  double heading = robot.yaw_rad;
  double goal_heading = goal.yaw_rad;
  if (allow_reverse && std::abs(WrapAngle(bearing - heading)) > std::numbers::pi / 2.0) {
    // Drive backwards: the same law for a robot whose front is its back.
    heading += std::numbers::pi;
    goal_heading += std::numbers::pi;
    out.reversing = true;
  }
  out.alpha = WrapAngle(bearing - heading);
  out.beta = WrapAngle(goal_heading - bearing);
  const double v = gains.k_rho * out.rho;
  out.twist.linear_mps = out.reversing ? -v : v;
  out.twist.angular_rps = gains.k_alpha * out.alpha + gains.k_beta * out.beta;
  return out;
}

}  // namespace corridor::nav
