// What the configuration holds for an RPLIDAR (rplidar_laser.h), without the driver itself.
#pragma once

#include <filesystem>

#include "drivers/rplidar/rplidar_protocol.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers::rplidar {

struct RplidarOptions {
  std::filesystem::path port;  // a serial device: /dev/ttyUSB0, /dev/corridor/rplidar
  int baud_rate = 115200;      // A1/A2: 115200; A3: 256000; S1/S2/C1: 256000 or 460800 (the device's fixed rate)
  nav::Pose2 base_T_laser;     // where it is mounted, base frame
  double height_m = 0.2;
  ScanMode scan_mode = ScanMode::kStandard;  // express: twice the samples, from firmware 1.17 (A1 since 2016)
  SweepOptions sweep;
  double stale_s = 0.05;     // no measurement for this long: the link is stale (the robot stops until they flow)
  double silence_s = 0.5;    // no measurement for this long: the port is opened and the device started again
  double reconnect_s = 0.5;  // between attempts to open a port that failed or went away
  double answer_s = 1.0;     // a request's descriptor must arrive within this
};

}  // namespace corridor::drivers::rplidar
