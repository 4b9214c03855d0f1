// What the devices served over DDS read and write (drivers/dds/devices.h), apart from DDS itself: the configuration
// holds these.
#pragma once

#include <Eigen/Geometry>

#include <cctype>
#include <string>

#include "drivers/diff_drive_base.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers::dds {

// A name ROS 2 takes for a topic: "/a/b_c" or "a/b" (letters, digits, '_' and '/'; a letter first; no empty part).
inline bool IsRosTopicName(const std::string& name) {
  const std::string n = !name.empty() && name.front() == '/' ? name.substr(1) : name;
  if (n.empty() || !std::isalpha(static_cast<unsigned char>(n.front())) || n.back() == '/' ||
      n.find("//") != std::string::npos) {
    return false;
  }
  for (char c : n) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '/') return false;
  }
  return true;
}

struct DdsCameraOptions {
  std::string depth_topic = "/camera/depth/image_rect_raw";  // sensor_msgs/Image, 16UC1 (mm) or 32FC1 (m)
  std::string info_topic = "/camera/depth/camera_info";      // sensor_msgs/CameraInfo
  std::string color_topic;  // bgr8 or rgb8 of the same size, registered to depth; empty: none (frames are black)
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();  // the optical frame in the base frame
  double min_range_m = 0.2;
  double max_range_m = 6.0;
};

struct DdsLaserOptions {
  std::string topic = "/scan";  // sensor_msgs/LaserScan
  nav::Pose2 base_T_laser;
  double height_m = 0.2;
};

struct DdsBaseOptions {
  std::string odom_topic = "/odom";        // nav_msgs/Odometry from the base driver
  std::string cmd_vel_topic = "/cmd_vel";  // geometry_msgs/Twist to it
  BaseLimits limits;
};

}  // namespace corridor::drivers::dds
