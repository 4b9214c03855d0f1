// What the configuration holds for a TurtleBot 3's laser (lds_laser.h), without the driver itself.
#pragma once

#include <filesystem>

#include "drivers/laser_sweep.h"
#include "drivers/lds/lds_protocol.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers::lds {

struct LdsOptions {
  Model model = Model::kLds02;  // lds-02 (LDROBOT LD08, TurtleBot 3 since 2021) or lds-01 (Hitachi-LG HLS-LFCD2)
  std::filesystem::path port;   // its USB2LDS board's CP2102: /dev/ttyUSB0, /dev/corridor/lds
  int baud_rate = 230400;       // both models' fixed rate
  nav::Pose2 base_T_laser;      // where it is mounted, base frame
  double height_m = 0.17;       // a Burger's
  // 360 beams; the LDS-01 measures 0.12-3.5 m, the LDS-02 0.16-8 m.
  SweepOptions sweep = {.bins = 360, .range_min_m = 0.12, .range_max_m = 8.0, .min_quality = 1, .min_points = 180};
  double stale_s = 0.05;     // no packet for this long: the link is stale (the robot stops until packets come)
  double silence_s = 0.5;    // no packet for this long: the port is reopened (and an LDS-01 started again)
  double reconnect_s = 0.5;  // between attempts to open a port that failed or went away
};

}  // namespace corridor::drivers::lds
