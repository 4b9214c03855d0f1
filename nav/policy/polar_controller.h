// The polar-coordinate pose controller (Wang et al., after Siegwart and Nourbakhsh, "Introduction to Autonomous
// Mobile Robots", section 3.6.2): with rho the distance to the goal, alpha the goal's bearing from the robot's
// heading and beta the bearing's angle to the goal heading (negated),
//   v = k_rho * rho,   w = k_alpha * alpha + k_beta * beta,
// which converges to the goal pose when k_rho > 0, k_beta < 0 and k_alpha - k_rho > 0.
#pragma once

#include <stdexcept>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct PolarGains {
  double k_rho = 0.6;
  double k_alpha = 2.0;
  double k_beta = -0.8;
};

// Throws std::invalid_argument naming the violated condition.
void ValidateGains(const PolarGains& gains);

struct PolarCommand {
  Twist2 twist;
  double rho = 0.0;
  double alpha = 0.0;
  double beta = 0.0;
  bool reversing = false;
};

// One control step toward `goal` from `robot` (both in the same frame). With allow_reverse the robot backs up
// to goals behind it (|alpha| > 90 degrees) instead of turning around. Speeds are not limited here.
PolarCommand PolarControl(const Pose2& robot, const Pose2& goal, const PolarGains& gains, bool allow_reverse);

}  // namespace corridor::nav
