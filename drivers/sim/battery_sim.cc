#include "drivers/sim/battery_sim.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::drivers::sim {

BatterySim::BatterySim(const SimBatteryOptions& options) : options_(options) {
  const SimBatteryOptions& o = options;
  if (!(o.capacity_wh > 0.0)) throw std::invalid_argument("battery capacity must be positive");
  if (!(o.initial_percent >= 0.0 && o.initial_percent <= 100.0)) {
    throw std::invalid_argument("battery initial percent must be between 0 and 100");
  }
  if (!(o.idle_w >= 0.0 && o.drive_w_per_mps >= 0.0 && o.turn_w_per_rps >= 0.0 && o.charge_w >= 0.0)) {
    throw std::invalid_argument("battery powers must not be negative");
  }
  if (!(o.taper_from > 0.0 && o.taper_from <= 1.0)) throw std::invalid_argument("battery taper_from must be in (0, 1]");
  if (!(o.full_v > o.empty_v && o.empty_v > 0.0)) throw std::invalid_argument("battery full_v must exceed empty_v > 0");
  charge_ = o.initial_percent / 100.0;
}

void BatterySim::Step(double dt_s, const nav::Twist2& velocity, bool on_charger) {
  const SimBatteryOptions& o = options_;
  const double load_w =
      o.idle_w + o.drive_w_per_mps * std::abs(velocity.linear_mps) + o.turn_w_per_rps * std::abs(velocity.angular_rps);
  // On the charger, the charger carries the robot's load and charges the pack with what its taper allows.
  double charge_w = 0.0;
  if (on_charger) {
    const double taper = charge_ <= o.taper_from ? 1.0 : (1.0 - charge_) / (1.0 - o.taper_from);
    charge_w = o.charge_w * std::clamp(taper, 0.0, 1.0);
  }
  power_w_ = on_charger ? charge_w : -load_w;
  charge_ = std::clamp(charge_ + power_w_ * dt_s / 3600.0 / o.capacity_wh, 0.0, 1.0);
  on_charger_ = on_charger;
}

BatteryState BatterySim::State(TimeNs stamp_ns) const {
  BatteryState s;
  s.stamp_ns = stamp_ns;
  s.charge = charge_;
  s.voltage_v = options_.empty_v + (options_.full_v - options_.empty_v) * charge_;
  s.current_a = power_w_ / s.voltage_v;
  s.charging = power_w_ > 0.0;
  s.on_charger = on_charger_;
  return s;
}

}  // namespace corridor::drivers::sim
