// The battery interface: the state of charge and whether the robot stands on its charger, as a base or a battery
// management board reports them. Bases that report nothing have no Battery.
#pragma once

#include <functional>

#include "drivers/clock.h"

namespace corridor::drivers {

struct BatteryState {
  TimeNs stamp_ns = 0;
  double charge = 1.0;  // state of charge, 0 (empty) to 1 (full)
  double voltage_v = 0.0;
  double current_a = 0.0;   // into the battery: positive while charging, negative while discharging (as ROS's
                            // sensor_msgs/BatteryState)
  bool charging = false;    // current flows in
  bool on_charger = false;  // the charging contacts are connected (the robot stands on its dock)
};

class Battery {
 public:
  using BatteryHandler = std::function<void(const BatteryState&)>;

  Battery() = default;
  Battery(const Battery&) = delete;
  Battery& operator=(const Battery&) = delete;
  virtual ~Battery() = default;

  // Called on the driver's thread whenever the state is read (about once a second); must return quickly.
  virtual void SetBatteryHandler(BatteryHandler handler) = 0;
};

}  // namespace corridor::drivers
