// The differential-drive base interface: velocity commands in, wheel odometry and bumper out.
#pragma once

#include <functional>

#include "drivers/clock.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers {

struct BaseLimits {
  double max_linear_mps = 0.0;
  double max_angular_rps = 0.0;
  double max_linear_accel_mps2 = 0.0;
  double max_angular_accel_rps2 = 0.0;
  double footprint_radius_m = 0.0;
};

// Wheel odometry: the base's dead-reckoned pose in its odometry frame (drifts), its measured velocity, whether the
// bumper is pressed, and whether the base sees a cliff or a dropped wheel (bases without such sensors say no).
struct WheelOdometry {
  TimeNs stamp_ns = 0;
  nav::Pose2 odom_T_base;
  nav::Twist2 velocity;
  bool bumper_pressed = false;
  bool cliff = false;
};

class DiffDriveBase {
 public:
  using OdometryHandler = std::function<void(const WheelOdometry&)>;

  DiffDriveBase() = default;
  DiffDriveBase(const DiffDriveBase&) = delete;
  DiffDriveBase& operator=(const DiffDriveBase&) = delete;
  virtual ~DiffDriveBase() = default;

  virtual BaseLimits limits() const = 0;
  // Requests a body velocity. The base clamps it to its limits and ramps with its acceleration limits. A base
  // stops by itself when commands stop arriving for its own timeout. Thread-safe.
  virtual void SetVelocity(const nav::Twist2& command) = 0;
  // Called on the driver's thread at the odometry rate; must return quickly.
  virtual void SetOdometryHandler(OdometryHandler handler) = 0;
};

}  // namespace corridor::drivers
