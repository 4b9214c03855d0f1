// What the configuration holds for a Hokuyo scanner (hokuyo_laser.h), without the driver itself.
#pragma once

#include <string>

#include "nav/geometry/pose2.h"

namespace corridor::drivers::hokuyo {

struct HokuyoOptions {
  // A serial device (/dev/ttyACM0, /dev/corridor/hokuyo: URG-04LX, UTM-30LX) or host:port (a UST-10LX/20LX on
  // Ethernet: 192.168.0.10:10940, its factory address).
  std::string port;
  int baud_rate = 115200;   // a USB URG ignores it
  nav::Pose2 base_T_laser;  // where it is mounted, base frame (upright)
  double height_m = 0.2;
  double min_range_m = 0.0;   // nearer ranges are dropped, as well as those below the device's own minimum
  double max_range_m = 60.0;  // farther ones too, as well as those beyond the device's own maximum
  // No scan for this long: the link is stale (the robot stops until scans come again); 0: one and a half of the
  // device's scan periods and 10 ms (47.5 ms for a 40 Hz UST, 160 ms for a 10 Hz URG-04LX).
  double stale_s = 0.0;
  double silence_s = 0.5;    // no scan for this long: the device is restarted
  double reconnect_s = 0.5;  // between attempts to open a port (or connect) that failed or went away
  double answer_s = 1.0;     // a command's answer must arrive within this (and a TCP connection be made)
};

}  // namespace corridor::drivers::hokuyo
