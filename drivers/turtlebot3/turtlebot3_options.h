// What the configuration holds for a TurtleBot 3 (turtlebot3_base.h), without the driver itself.
#pragma once

#include <filesystem>

#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::turtlebot3 {

// A TurtleBot 3 Burger's wheels (e-Manual specifications): 66 mm across, 160 mm apart, XL430 servos counting 4096 a
// turn. A Waffle Pi's are 287 mm apart.
inline constexpr WheelGeometry kBurgerWheels{0.066, 0.160, 4096.0};

struct TurtleBot3Options {
  std::filesystem::path port;  // /dev/ttyACM0, /dev/corridor/opencr
  int baud_rate = 1000000;     // the OpenCR's
  WheelGeometry wheels = kBurgerWheels;
  double max_linear_mps = 0.22;   // the Burger's top speed (the Waffle Pi's 0.26)
  double max_angular_rps = 2.84;  // (the Waffle Pi's 1.82)
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_rps2 = 4.0;
  double footprint_radius_m = 0.105;  // around the Burger's 138 x 178 mm (the Waffle Pi's 281 x 306 mm: 0.21)
  double poll_period_s = 0.02;        // the board's state read this often
  double connect_s = 2.0;             // the board's first answer (to a ping) is awaited this long
  double heartbeat_period_s = 0.1;
  double command_timeout_s = 0.5;
  double stale_s = 0.08;   // no state read for this long: the link is stale, the robot stops
  double silence_s = 0.5;  // no state read for this long: the port is opened anew
  double reconnect_s = 0.5;
  double battery_period_s = 1.0;
};

}  // namespace corridor::drivers::turtlebot3
