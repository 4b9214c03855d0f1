// The camera's pan servo: what turns the camera about a vertical axis so that it can look where the robot needs to
// look (ASNS's gaze, nav/policy/gaze.h). Implementations: the simulator's (drivers/sim), a DYNAMIXEL servo
// (drivers/dynamixel/pan_servo.h).
//
// The camera's pose at a frame is the mount's pose turned by the pan angle the servo reported about the frame's
// stamp (PanHistory): a frame taken while the servo's angle is unknown is not used.
#pragma once

#include <functional>

#include <Eigen/Core>

#include "drivers/clock.h"

namespace corridor::drivers {

// The angles the servo may be sent to (radians, counter-clockwise seen from above, 0 looking straight ahead) and how
// fast it turns.
struct PanLimits {
  double min_rad = 0.0;
  double max_rad = 0.0;
  double max_speed_rps = 0.0;
};

// Where the servo was at a time, on the host's clock.
struct PanReading {
  TimeNs stamp_ns = 0;
  double pan_rad = 0.0;
  double velocity_rps = 0.0;
};

class PanServo {
 public:
  using ReadingHandler = std::function<void(const PanReading&)>;

  PanServo() = default;
  PanServo(const PanServo&) = delete;
  PanServo& operator=(const PanServo&) = delete;
  virtual ~PanServo() = default;

  virtual PanLimits pan_limits() const = 0;
  // Where its vertical axis stands in the base frame (x forward, y left): the camera turns about it
  // (nav::PanTurn).
  virtual Eigen::Vector2d axis_xy() const = 0;
  // Where to turn to; clamped to the limits. Thread-safe.
  virtual void SetTarget(double pan_rad) = 0;
  // Called on the driver's thread (or the simulator's step) with every reading; must return quickly.
  virtual void SetReadingHandler(ReadingHandler handler) = 0;
};

}  // namespace corridor::drivers
