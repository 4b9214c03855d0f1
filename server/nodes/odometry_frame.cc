#include "server/nodes/odometry_frame.h"

#include <algorithm>
#include <iterator>

namespace corridor::server {
namespace {

constexpr drivers::TimeNs kKeptNs = 1'000'000'000;

}  // namespace

nav::Pose2 OdometryFrame::Add(const drivers::WheelOdometry& odometry) {
  std::lock_guard lock(mutex_);
  odometry_.push_back(odometry);
  while (odometry_.size() > 2 && odometry_.back().stamp_ns - odometry_.front().stamp_ns > kKeptNs) {
    odometry_.pop_front();
  }
  return map_T_odom_ * odometry.odom_T_base;
}

std::optional<nav::Pose2> OdometryFrame::At(drivers::TimeNs stamp_ns) const {
  std::lock_guard lock(mutex_);
  if (odometry_.empty()) return std::nullopt;
  if (stamp_ns >= odometry_.back().stamp_ns) return odometry_.back().odom_T_base;
  if (stamp_ns <= odometry_.front().stamp_ns) return odometry_.front().odom_T_base;
  const auto after =
      std::lower_bound(odometry_.begin(), odometry_.end(), stamp_ns,
                       [](const drivers::WheelOdometry& o, drivers::TimeNs t) { return o.stamp_ns < t; });
  const auto before = std::prev(after);
  const double f = static_cast<double>(stamp_ns - before->stamp_ns) /
                   static_cast<double>(std::max<drivers::TimeNs>(1, after->stamp_ns - before->stamp_ns));
  return nav::Interpolate(before->odom_T_base, after->odom_T_base, f);
}

nav::Pose2 OdometryFrame::Latest() const {
  std::lock_guard lock(mutex_);
  return odometry_.empty() ? nav::Pose2{} : odometry_.back().odom_T_base;
}

nav::Pose2 OdometryFrame::map_T_odom() const {
  std::lock_guard lock(mutex_);
  return map_T_odom_;
}

void OdometryFrame::set_map_T_odom(const nav::Pose2& map_T_odom) {
  std::lock_guard lock(mutex_);
  map_T_odom_ = map_T_odom;
}

}  // namespace corridor::server
