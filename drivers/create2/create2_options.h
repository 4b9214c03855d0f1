// What the configuration holds for a Create 2 (create2_base.h), without the driver itself.
#pragma once

#include <filesystem>

#include "drivers/create2/open_interface.h"

namespace corridor::drivers::create2 {

struct Create2Options {
  std::filesystem::path port;  // /dev/ttyUSB0, /dev/corridor/create2
  int baud_rate = 115200;      // the OI's default
  WheelGeometry wheels = kCreate2Wheels;
  double max_linear_mps = 0.5;  // the OI's 500 mm/s a wheel
  double max_angular_rps = 4.0;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_rps2 = 4.0;
  double footprint_radius_m = 0.17;
  double command_timeout_s = 0.5;
  double stale_s = 0.05;   // no whole frame for this long: the link is stale (the robot stops until frames flow)
  double silence_s = 0.2;  // no whole frame for this long: the stream is restarted
  double reconnect_s = 0.5;
  double battery_period_s = 1.0;
};

}  // namespace corridor::drivers::create2
