// The last second of wheel odometry and where the odometry frame lies in the map (map_T_odom), shared by the
// localization node's executor (which moves map_T_odom after each scan and looks up the odometry at a scan's time)
// and the odometry topic's tap on the publisher's thread (which records each reading and turns it into the robot's
// pose in the map). Thread-safe. Held by shared_ptr: the tap may outlive the node.
#pragma once

#include <mutex>
#include <optional>

#include "drivers/diff_drive_base.h"
#include "nav/geometry/pose2.h"
#include "server/nodes/pose_history.h"

namespace corridor::server {

class OdometryFrame {
 public:
  explicit OdometryFrame(const nav::Pose2& map_T_odom) : map_T_odom_(map_T_odom) {}
  OdometryFrame(const OdometryFrame&) = delete;
  OdometryFrame& operator=(const OdometryFrame&) = delete;

  // Records a reading (stamps in order) and returns the robot's pose in the map by it.
  nav::Pose2 Add(const drivers::WheelOdometry& odometry);
  // The odometry (odom_T_base) at `stamp_ns`, interpolated between the readings around it (the first or last beyond
  // them); nullopt before any.
  std::optional<nav::Pose2> At(drivers::TimeNs stamp_ns) const { return odometry_.At(stamp_ns); }
  // The last reading's odom_T_base; the identity before any.
  nav::Pose2 Latest() const { return odometry_.Latest().value_or(nav::Pose2{}); }
  nav::Pose2 map_T_odom() const;
  void set_map_T_odom(const nav::Pose2& map_T_odom);

 private:
  PoseHistory odometry_;
  mutable std::mutex mutex_;  // guards map_T_odom_
  nav::Pose2 map_T_odom_;
};

}  // namespace corridor::server
