// What the configuration holds for a camera's DYNAMIXEL pan servo (pan_servo.h), without the driver itself.
#pragma once

#include <filesystem>

namespace corridor::drivers::dynamixel {

struct PanServoOptions {
  std::filesystem::path port;  // /dev/ttyUSB0 (a U2D2), /dev/corridor/pan
  int baud_rate = 57600;       // the X-series' factory setting
  int id = 1;                  // the factory setting
  int center_position = 2048;  // the count at which the camera looks straight ahead
  double axis_x_m = 0.1;       // its axis in the base frame: under the camera's optical centre, or behind it
  double axis_y_m = 0.0;
  bool reversed = false;    // true: counting up turns the camera clockwise seen from above (a servo hung upside down)
  double min_deg = -150.0;  // where the cable lets it turn
  double max_deg = 150.0;
  double max_speed_dps = 90.0;    // the profile velocity the servo is given
  double max_accel_dps2 = 360.0;  // and its profile acceleration
  double poll_period_s = 0.02;    // the position read this often
  double goal_refresh_s = 0.5;    // the goal written again this often even when unchanged (a servo restarted)
  double connect_s = 2.0;         // the servo's first answer (to a ping) is awaited this long
  double stale_s = 0.1;           // no position for this long: the camera's pose is unknown, its frames unused
  double silence_s = 0.5;         // no position for this long: the port is opened anew
  double reconnect_s = 0.5;
};

}  // namespace corridor::drivers::dynamixel
