// What the configuration holds for a home-made base on the serial text protocol (serial_text_base.h), without the
// driver itself.
#pragma once

#include <filesystem>

#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::serial_text {

struct SerialTextOptions {
  std::filesystem::path port;  // /dev/ttyACM0, /dev/ttyUSB0
  int baud_rate = 57600;       // ROSArduinoBridge's
  // The base's own wheels: no default, a home-made base has its own (the configuration requires them).
  WheelGeometry wheels;
  // `m`'s unit: encoder counts per 1/pid_rate_hz s (ROSArduinoBridge's PID_RATE, 30); 1 for a board whose `m` takes
  // counts a second.
  double pid_rate_hz = 30.0;
  double poll_period_s = 0.02;  // the encoders asked for this often
  double boot_s = 3.0;          // an Arduino restarts when its port is opened: its first answer is awaited this long
  double max_linear_mps = 0.3;
  double max_angular_rps = 2.0;
  double max_linear_accel_mps2 = 0.5;
  double max_angular_accel_rps2 = 2.0;
  double footprint_radius_m = 0.15;
  double command_timeout_s = 0.5;
  double stale_s = 0.08;   // no encoder reply for this long: the link is stale, the robot stops
  double silence_s = 0.5;  // no reply for this long: the port is opened anew (the board restarts)
  double reconnect_s = 1.0;
  double battery_period_s = 1.0;  // unused: the protocol has no battery
};

}  // namespace corridor::drivers::serial_text
