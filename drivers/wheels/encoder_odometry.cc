#include "drivers/wheels/encoder_odometry.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace corridor::drivers {

int CountsDelta(std::uint16_t before, std::uint16_t now) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(now - before));
}

double CountsToMetres(int counts, const WheelGeometry& wheels) {
  return counts * std::numbers::pi * wheels.wheel_diameter_m / wheels.counts_per_revolution;
}

EncoderOdometry::EncoderOdometry(const WheelGeometry& wheels, double velocity_window_s)
    : wheels_(wheels), window_s_(velocity_window_s) {
  if (!wheels.Valid() || !(velocity_window_s > 0.0)) {
    throw std::invalid_argument("encoder odometry: wheel diameter, track, counts per turn and window must be positive");
  }
}

void EncoderOdometry::Restart() {
  last_counts_.reset();
  travelled_.clear();
  velocity_ = {};
}

void EncoderOdometry::Update(TimeNs now, std::uint16_t left, std::uint16_t right) {
  if (last_counts_) {
    const double l = CountsToMetres(CountsDelta(last_counts_->first, left), wheels_);
    const double r = CountsToMetres(CountsDelta(last_counts_->second, right), wheels_);
    const double ds = 0.5 * (l + r);
    const double dyaw = (r - l) / wheels_.track_m;
    pose_ = pose_ * nav::Pose2{ds * std::cos(0.5 * dyaw), ds * std::sin(0.5 * dyaw), dyaw};
    distance_m_ += ds;
    yaw_rad_ += dyaw;
  }
  last_counts_ = std::make_pair(left, right);
  travelled_.push_back({now, distance_m_, yaw_rad_});
  while (travelled_.size() > 2 && ToSeconds(now - travelled_[1].stamp_ns) >= window_s_) travelled_.pop_front();
  const Travelled& then = travelled_.front();
  const double span_s = ToSeconds(now - then.stamp_ns);
  velocity_ = span_s > 0.0 ? nav::Twist2{(distance_m_ - then.distance_m) / span_s, (yaw_rad_ - then.yaw_rad) / span_s}
                           : nav::Twist2{};
}

}  // namespace corridor::drivers
