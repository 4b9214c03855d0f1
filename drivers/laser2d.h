// The planar laser scanner interface.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <vector>

#include "drivers/clock.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers {

// One sweep. ranges[i] is the distance in metres along angle_min_rad + i * angle_increment_rad (laser frame,
// counter-clockwise from forward); +infinity where nothing was hit within range_max_m.
//
// A rotating laser measures its beams one after another while the robot moves (at 1 rad/s, an RPLIDAR's 10 Hz turn
// sees its first beams 6 degrees away from its last): sweep_s says how. The laser turned from sweep_start_rad (laser
// frame) clockwise or counter-clockwise through the whole turn in sweep_s, ending at stamp_ns. 0: every beam at the
// stamp (the simulator's laser, one from ROS 2 without timing).
struct LaserScan {
  TimeNs stamp_ns = 0;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges;
  double sweep_s = 0.0;
  double sweep_start_rad = 0.0;
  bool sweep_clockwise = true;
};

// How long before the scan's stamp beam i was measured, seconds in [0, sweep_s].
inline double BeamAgeS(const LaserScan& scan, std::size_t i) {
  if (!(scan.sweep_s > 0.0)) return 0.0;
  constexpr double kTurn = 2.0 * std::numbers::pi;
  const double angle = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
  const double turned = scan.sweep_clockwise ? scan.sweep_start_rad - angle : angle - scan.sweep_start_rad;
  const double fraction = (turned - kTurn * std::floor(turned / kTurn)) / kTurn;  // of the turn done at this beam
  return (1.0 - fraction) * scan.sweep_s;
}

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
