// What the configuration holds for DDS without DDS itself: the devices served over DDS (drivers/dds/devices.h), and
// the checks of names and addresses it shares with the participant.
#pragma once

#include <arpa/inet.h>
#include <unistd.h>

#include <array>
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

// A dotted IPv4 address ("192.168.1.20").
inline bool IsIpv4Address(const std::string& text) {
  in_addr address{};
  return ::inet_pton(AF_INET, text.c_str(), &address) == 1;
}

// The files of a DDS Security enclave, in its directory: ROS 2's layout (`ros2 security create_enclave`), which
// tools/dds-keystore makes too.
inline constexpr std::array<const char*, 6> kEnclaveFiles = {
    "identity_ca.cert.pem", "cert.pem", "key.pem", "permissions_ca.cert.pem", "governance.p7s", "permissions.p7s"};

// The first of an enclave's files in `directory` this process cannot read; "" when it can read them all.
inline std::string UnreadableEnclaveFile(const std::string& directory) {
  for (const char* file : kEnclaveFiles) {
    const std::string path = directory + "/" + file;
    if (::access(path.c_str(), R_OK) != 0) return path;
  }
  return "";
}

struct DdsCameraOptions {
  std::string depth_topic = "/camera/depth/image_rect_raw";  // sensor_msgs/Image, 16UC1 (mm) or 32FC1 (m)
  std::string info_topic = "/camera/depth/camera_info";      // sensor_msgs/CameraInfo
  std::string color_topic;  // bgr8 or rgb8 of the same size, registered to depth; empty: none (frames are black)
  double mount_x_m = 0.1;   // the optical centre: forward of the base's centre, above the floor, pitched down
  double mount_height_m = 0.3;
  double tilt_deg = 10.0;
  double min_range_m = 0.2;
  double max_range_m = 6.0;
};

struct DdsLaserOptions {
  std::string topic;  // sensor_msgs/LaserScan, e.g. /scan; empty: no laser
  nav::Pose2 base_T_laser;
  double height_m = 0.2;
};

struct DdsBaseOptions {
  std::string odom_topic = "/odom";        // nav_msgs/Odometry from the base driver
  std::string cmd_vel_topic = "/cmd_vel";  // geometry_msgs/Twist to it
  // sensor_msgs/BatteryState from it (kobuki_node's, turtlebot3_node's /battery_state); "": the base reports none.
  std::string battery_topic;
  BaseLimits limits{0.5, 1.5, 1.0, 3.0, 0.2};
};

}  // namespace corridor::drivers::dds
