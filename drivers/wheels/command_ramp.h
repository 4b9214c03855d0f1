// A base's wheel command ramped toward what is asked, within its acceleration limits, one step at a time (the native
// base drivers send one command per sensor report).
#pragma once

#include <algorithm>

#include "nav/geometry/pose2.h"

namespace corridor::drivers {

// `from` moved toward `to` by at most the accelerations over dt_s.
inline nav::Twist2 RampToward(const nav::Twist2& from, const nav::Twist2& to, double max_linear_accel_mps2,
                              double max_angular_accel_rps2, double dt_s) {
  const auto ramp = [](double a, double b, double step) { return a + std::clamp(b - a, -step, step); };
  return {ramp(from.linear_mps, to.linear_mps, max_linear_accel_mps2 * dt_s),
          ramp(from.angular_rps, to.angular_rps, max_angular_accel_rps2 * dt_s)};
}

}  // namespace corridor::drivers
