// Reading laser logs in the CARMEN format (Montemerlo, Roy and Thrun, CARMEN robot navigation toolkit; the format of
// the Radish datasets and of Kuemmerle et al.'s SLAM benchmark, 2009): one message per line; FLASER lines carry a
// front laser sweep with the robot's pose. Plain or gzip-compressed.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct CarmenScan {
  double timestamp_s = 0.0;    // the message's ipc timestamp
  Pose2 pose;                  // the laser's pose as logged (in "corrected" logs, the corrected pose)
  double angle_min_rad = 0.0;  // the sweep: ranges[i] along angle_min_rad + i * angle_increment_rad
  double angle_increment_rad = 0.0;
  std::vector<float> ranges_m;
};

struct CarmenLog {
  std::vector<CarmenScan> scans;  // FLASER messages, in the log's order
};

// A file that cannot be read or a FLASER line that does not parse; what() names the file and line.
class CarmenLogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads every FLASER message (other messages are skipped). The old FLASER carries no angles: a sweep of n readings
// covers fov_rad centred ahead, at fov / n apart for even n (180 readings: 1 degree, the last one dropped by the
// logger) and fov / (n - 1) for odd n (181: both ends). Throws CarmenLogError.
CarmenLog ReadCarmenLog(const std::filesystem::path& path, double fov_rad = 3.14159265358979323846);

}  // namespace corridor::nav
