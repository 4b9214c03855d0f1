#include "server/nodes/odometry_frame.h"

namespace corridor::server {

nav::Pose2 OdometryFrame::Add(const drivers::WheelOdometry& odometry) {
  odometry_.Add(odometry.stamp_ns, odometry.odom_T_base);
  return map_T_odom() * odometry.odom_T_base;
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
