// Odometry of a differential base from its wheels' encoder counts, as the native bases report them (Create 2, Kobuki):
// 16-bit counts that wrap either way, turned into the base's pose in its odometry frame (midpoint integration, one
// step per report) and its velocity over a short window (reports arrive bunched on a busy host: one report's counts
// over its arrival gap were off by a quarter).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

#include "drivers/clock.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers {

struct WheelGeometry {
  double wheel_diameter_m = 0.0;
  double track_m = 0.0;                // between the wheels' contact points
  double counts_per_revolution = 0.0;  // encoder counts for one turn of a wheel
  bool Valid() const { return wheel_diameter_m > 0.0 && track_m > 0.0 && counts_per_revolution > 0.0; }
};

// The counts' change from `before` to `now`, across the wrap at 65535 either way (a wheel turns far less than half
// the range between two reports).
int CountsDelta(std::uint16_t before, std::uint16_t now);
// How far a wheel rolled for `counts` encoder counts.
double CountsToMetres(int counts, const WheelGeometry& wheels);

class EncoderOdometry {
 public:
  // Throws std::invalid_argument for a geometry that is not positive.
  explicit EncoderOdometry(const WheelGeometry& wheels, double velocity_window_s = 0.1);

  // The counts reported at `now`: the pose moves by the wheels' travel since the counts before (the first counts, and
  // the first after Restart, only set where counting starts).
  void Update(TimeNs now, std::uint16_t left, std::uint16_t right);
  // The device started anew (power-cycled, reconnected): its counts start anew; the pose stays where it was.
  void Restart();

  const nav::Pose2& pose() const { return pose_; }
  // Over the last velocity_window_s of updates; zero before two.
  const nav::Twist2& velocity() const { return velocity_; }

 private:
  struct Travelled {
    TimeNs stamp_ns;
    double distance_m;
    double yaw_rad;
  };
  WheelGeometry wheels_;
  double window_s_;
  std::optional<std::pair<std::uint16_t, std::uint16_t>> last_counts_;  // left, right
  nav::Pose2 pose_;
  nav::Twist2 velocity_;
  double distance_m_ = 0.0;  // along the way, and turned, since the start
  double yaw_rad_ = 0.0;
  std::deque<Travelled> travelled_;
};

}  // namespace corridor::drivers
