// The planar laser scanner interface.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "drivers/clock.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers {

// One sweep. ranges[i] is the distance in metres along angle_min_rad + i * angle_increment_rad (laser frame,
// counter-clockwise from forward); +infinity where nothing was hit within range_max_m.
struct LaserScan {
  TimeNs stamp_ns = 0;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges;
};

class Laser2D {
 public:
  using ScanHandler = std::function<void(std::shared_ptr<const LaserScan>)>;

  Laser2D() = default;
  Laser2D(const Laser2D&) = delete;
  Laser2D& operator=(const Laser2D&) = delete;
  virtual ~Laser2D() = default;

  // Pose of the laser in the robot base frame, and its mounting height above the floor.
  virtual nav::Pose2 base_T_laser() const = 0;
  virtual double height_m() const = 0;
  // Called on the driver's thread for every sweep; must return quickly.
  virtual void SetScanHandler(ScanHandler handler) = 0;
};

}  // namespace corridor::drivers
