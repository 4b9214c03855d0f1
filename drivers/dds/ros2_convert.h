// Between corridor's types and ROS 2 messages (REP 103: x forward, y left, z up, metres, radians; REP 105 frames).
// Stamps: corridor's clocks count from an arbitrary epoch; ROS 2 tools expect the system's time, so a StampClock
// shifts them by a fixed offset taken once. Everything here is a pure function but for that offset.
#pragma once

#include <opencv2/core.hpp>

#include <optional>
#include <string>

#include "drivers/battery.h"
#include "drivers/clock.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "nav/geometry/pose2.h"
#include "ros2/builtin_interfaces.h"
#include "ros2/geometry_msgs.h"
#include "ros2/nav_msgs.h"
#include "ros2/sensor_msgs.h"

namespace corridor::drivers::dds {

// REP 105's frame names.
inline constexpr const char* kMapFrame = "map";
inline constexpr const char* kOdomFrame = "odom";
inline constexpr const char* kBaseFrame = "base_link";
inline constexpr const char* kLaserFrame = "laser";
inline constexpr const char* kCameraFrame = "camera_depth_optical_frame";

// A clock's time <-> ROS 2 stamps (system time). Thread-safe (immutable).
class StampClock {
 public:
  // `offset_ns`: added to the clock's time to give the system's time.
  explicit StampClock(TimeNs offset_ns = 0) : offset_ns_(offset_ns) {}
  // The offset that maps `clock`'s now to the system's now.
  static StampClock For(const Clock& clock);
  builtin_interfaces::msg::Time ToRos(TimeNs t) const;
  TimeNs FromRos(const builtin_interfaces::msg::Time& stamp) const;

 private:
  TimeNs offset_ns_;
};

std_msgs::msg::Header Header(const builtin_interfaces::msg::Time& stamp, const std::string& frame);

geometry_msgs::msg::Quaternion YawQuaternion(double yaw_rad);
// The rotation about z of `q` (its roll and pitch are dropped); throws std::invalid_argument for a zero or not
// finite quaternion.
double YawOf(const geometry_msgs::msg::Quaternion& q);
geometry_msgs::msg::Pose ToRos(const nav::Pose2& pose);
// Throws std::invalid_argument for a pose that is not finite.
nav::Pose2 FromRos(const geometry_msgs::msg::Pose& pose);
geometry_msgs::msg::Transform ToTransform(const Eigen::Isometry3d& t);
geometry_msgs::msg::TransformStamped Transform(const builtin_interfaces::msg::Time& stamp, const std::string& parent,
                                               const std::string& child, const Eigen::Isometry3d& parent_T_child);

geometry_msgs::msg::Twist ToRos(const nav::Twist2& twist);
// The planar part of a twist (linear.x, angular.z); throws std::invalid_argument when they are not finite.
nav::Twist2 FromRos(const geometry_msgs::msg::Twist& twist);

// Odometry in the odom frame of base_link, with the twist in base_link.
nav_msgs::msg::Odometry ToRos(const WheelOdometry& odometry, const StampClock& clock);
// Throws std::invalid_argument for odometry that is not finite.
WheelOdometry FromRos(const nav_msgs::msg::Odometry& odometry, const StampClock& clock);

// A scan in `frame`; +infinity stays +infinity (REP 117: nothing within range). A sweep's duration goes in
// scan_time (its beams' times are not in index order: time_increment stays 0).
sensor_msgs::msg::LaserScan ToRos(const LaserScan& scan, const StampClock& clock, const std::string& frame);
// Throws std::invalid_argument for a scan whose angles or limits are not usable. A positive time_increment (the beams
// measured in index order from the stamp, a rotating laser's) becomes the sweep's timing, stamped after its last
// beam.
LaserScan FromRos(const sensor_msgs::msg::LaserScan& scan, const StampClock& clock);

// The battery as sensor_msgs/BatteryState: percentage 0-1, current positive while charging, status charging,
// discharging, or full (on the charger and not charging); what corridor does not know is NaN.
sensor_msgs::msg::BatteryState ToRos(const BatteryState& battery, const StampClock& clock);
// From a base driver's: the charge from the percentage (0-1; some drivers send 0-100, taken as such above 1), charging
// from the status, on the charger while charging or full. Throws std::invalid_argument when the percentage is not a
// number in 0-100.
BatteryState FromRos(const sensor_msgs::msg::BatteryState& battery, const StampClock& clock);

// A scan in `frame` from points in that frame (a depth camera's nearest obstacle per column): the nearest point in
// each `increment_rad` of bearing over the points' span; +infinity where no point falls.
sensor_msgs::msg::LaserScan ScanFromPoints(const std::vector<Eigen::Vector2d>& points, double increment_rad,
                                           double range_min_m, double range_max_m,
                                           const builtin_interfaces::msg::Time& stamp, const std::string& frame);

// A 16UC1 depth image in millimetres (REP 118 allows 16UC1 mm or 32FC1 m).
sensor_msgs::msg::Image DepthImage(const cv::Mat& depth_mm, const builtin_interfaces::msg::Time& stamp,
                                   const std::string& frame);
// Depth in millimetres (CV_16UC1) from a 16UC1 (mm) or 32FC1 (m; NaN and non-positive as no measurement) image.
// Throws std::invalid_argument for another encoding, a big-endian image or data shorter than step * height.
cv::Mat DepthFromRos(const sensor_msgs::msg::Image& image);
// A colour image (CV_8UC3 BGR) from bgr8 or rgb8; throws std::invalid_argument for anything else.
cv::Mat ColorFromRos(const sensor_msgs::msg::Image& image);

// The pinhole intrinsics without distortion (plumb_bob with zero coefficients).
sensor_msgs::msg::CameraInfo ToRos(const nav::PinholeCamera& camera, const builtin_interfaces::msg::Time& stamp,
                                   const std::string& frame);
// The intrinsics of a CameraInfo (its K); the camera's pose in the base frame stays `base_T_camera`. Throws
// std::invalid_argument for a size or focal length that cannot be used.
nav::PinholeCamera FromRos(const sensor_msgs::msg::CameraInfo& info, const Eigen::Isometry3d& base_T_camera);

}  // namespace corridor::drivers::dds
