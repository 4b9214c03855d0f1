// What the configuration holds for a Kobuki (kobuki_base.h), without the driver itself.
#pragma once

#include <filesystem>

#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::kobuki {

// The Kobuki's wheels (Kobuki user guide): 70 mm across, 230 mm apart, 2578.33 encoder counts a turn (11.7 a mm).
inline constexpr WheelGeometry kKobukiWheels{0.070, 0.230, 2578.33};

struct KobukiOptions {
  std::filesystem::path port;  // /dev/ttyUSB0, /dev/corridor/kobuki
  int baud_rate = 115200;      // the protocol's
  WheelGeometry wheels = kKobukiWheels;
  double max_linear_mps = 0.7;    // the Kobuki's top speed
  double max_angular_rps = 3.14;  // its 180 degrees a second
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_rps2 = 4.0;
  double footprint_radius_m = 0.177;  // 354 mm across
  double command_timeout_s = 0.5;
  double stale_s = 0.05;   // no feedback (every 20 ms) for this long: the link is stale, the robot stops
  double silence_s = 0.2;  // no feedback for this long: the port is opened anew
  double reconnect_s = 0.5;
  double battery_period_s = 1.0;
  // Its 4-cell lithium-ion pack (14.8 V nominal), read as empty at this voltage and full at that one: the Kobuki
  // reports only the voltage.
  double battery_empty_v = 13.2;
  double battery_full_v = 16.5;
};

}  // namespace corridor::drivers::kobuki
