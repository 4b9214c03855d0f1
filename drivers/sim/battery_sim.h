// The simulated battery: a pack that drains with time (the computer and sensors) and with motion (the wheels'
// motors), and charges on the dock at constant power up to taper_from, then tapering to full (the constant-current,
// constant-voltage shape of a lithium-ion charger). Its voltage is the open-circuit voltage, linear in the charge
// between empty_v and full_v: enough for a console and a fleet manager, not a cell model.
#pragma once

#include "drivers/battery.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers::sim {

struct SimBatteryOptions {
  double capacity_wh = 40.0;      // a 3S 3.6 Ah pack
  double initial_percent = 80.0;  // at start-up
  double idle_w = 8.0;            // the computer, the camera, the screen
  double drive_w_per_mps = 12.0;  // the wheels' motors, per metre a second
  double turn_w_per_rps = 3.0;    // and per radian a second of turning
  double charge_w = 30.0;         // what the dock delivers until taper_from
  double taper_from = 0.8;        // above this charge, the charging power falls linearly to 0 at full
  double empty_v = 10.5;
  double full_v = 12.6;
  double rate_hz = 1.0;  // how often the state is reported
};

// Not thread-safe: the simulator steps it on its thread.
class BatterySim {
 public:
  // Throws std::invalid_argument for options out of range.
  explicit BatterySim(const SimBatteryOptions& options);

  // dt_s of driving at `velocity`, on the charger or not.
  void Step(double dt_s, const nav::Twist2& velocity, bool on_charger);
  BatteryState State(TimeNs stamp_ns) const;
  double charge() const { return charge_; }

 private:
  SimBatteryOptions options_;
  double charge_ = 1.0;
  double power_w_ = 0.0;  // into the pack during the last step (negative: out)
  bool on_charger_ = false;
};

}  // namespace corridor::drivers::sim
