#include "nav/safety/stopping.h"

#include <algorithm>
#include <cmath>

namespace corridor::nav {

double StoppingDistance(double speed_mps, const StoppingModel& m) {
  const double v = std::max(0.0, speed_mps);
  return v * m.reaction_time_s + v * v / (2.0 * m.max_decel_mps2) + m.margin_m;
}

double SpeedForFreeDistance(double free_m, const StoppingModel& m) {
  const double d = free_m - m.margin_m;
  if (d <= 0.0) return 0.0;
  // v^2 / (2a) + v t - d = 0  =>  v = a (-t + sqrt(t^2 + 2 d / a))
  const double a = m.max_decel_mps2;
  const double t = m.reaction_time_s;
  return a * (-t + std::sqrt(t * t + 2.0 * d / a));
}

bool NeedsProtectiveStop(double obstacle_m, double speed_mps, const StoppingModel& m) {
  return obstacle_m < StoppingDistance(speed_mps, m);
}

}  // namespace corridor::nav
