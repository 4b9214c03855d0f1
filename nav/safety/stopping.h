// Speed limits from free space: the robot must always be able to stop before the nearest obstacle it sees.
// Stopping distance at speed v with reaction time t and deceleration a: d(v) = v t + v^2 / (2 a), plus a margin.
#pragma once

namespace corridor::nav {

struct StoppingModel {
  double max_decel_mps2 = 0.8;   // braking the base can always achieve
  double reaction_time_s = 0.1;  // from the frame that shows the obstacle to the wheels braking
  double margin_m = 0.1;         // kept between the robot's front and the obstacle when stopped
};

// Distance needed to stop from `speed_mps` (>= 0), margin included.
double StoppingDistance(double speed_mps, const StoppingModel& model);

// The highest speed from which the robot stops within `free_m` (the inverse of StoppingDistance); 0 when free_m is
// within the margin.
double SpeedForFreeDistance(double free_m, const StoppingModel& model);

// True when an obstacle at `obstacle_m` is inside the stopping distance at `speed_mps`: stop now.
bool NeedsProtectiveStop(double obstacle_m, double speed_mps, const StoppingModel& model);

}  // namespace corridor::nav
