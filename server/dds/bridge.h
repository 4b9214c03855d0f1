// The DDS bridge: the bus as ROS 2 topics, a subscriber of the bus like the WebSocket stream. Each row of its table
// (bridge.cc, Activate) takes one bus topic to one ROS 2 topic with ROS 2's type, frame and QoS; adding a row exposes
// another topic. What ROS 2 tools send (/cmd_vel, /goal_pose, /initialpose) goes the way the console's commands go:
// velocity onto the teleop topic (the command gate's deadman, limits and protective stop apply), goals and poses
// through the robot core (server/app/robot_core.h: the same checks; a refusal is logged). Those writes are taken only
// with dds.allow_writes: DDS has no authentication here.
//
// Frames (REP 105): map -> odom (localization, dated ahead by kMapOdomToleranceS as AMCL does), odom -> base_link
// (odometry), base_link -> laser and base_link -> camera_depth_optical_frame on /tf_static.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <string>

#include "drivers/dds/participant.h"
#include "drivers/dds/ros2_convert.h"
#include "ros2/diagnostic_msgsPubSubTypes.h"
#include "ros2/geometry_msgsPubSubTypes.h"
#include "ros2/nav_msgsPubSubTypes.h"
#include "ros2/sensor_msgsPubSubTypes.h"
#include "ros2/std_msgsPubSubTypes.h"
#include "ros2/tf2_msgsPubSubTypes.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/runtime/node.h"
#include "server/store/map_library.h"

namespace corridor::server {

// The participant dds.* asks for (the domain from DdsDomain), shared by the bridge and the devices over DDS.
std::unique_ptr<drivers::dds::Participant> MakeParticipant(const DdsOptions& dds);

// What the bridge publishes about the robot's body, from its devices.
struct RobotFrames {
  std::optional<Eigen::Isometry3d> base_T_laser;  // none: no laser (/scan then comes from the depth camera)
  std::optional<drivers::CameraInfo> camera;      // with its pose in the base frame, and its range; none: no camera
  // Devices served by ROS 2 drivers (drivers/dds/devices.h) publish themselves what the bridge would: the base its
  // odometry and odom -> base_link, the laser its scans, the camera its images.
  bool base_over_dds = false;
  bool laser_over_dds = false;
  bool camera_over_dds = false;
};

class DdsBridge final : public PeriodicNode {
 public:
  // Everything must outlive the bridge. `core`: the state it publishes, where goals and poses go.
  DdsBridge(Executor& executor, Bus& bus, drivers::dds::Participant& participant, const DdsOptions& options,
            RobotFrames frames, const RobotCore& core, const MapLibrary& maps, const Lifecycle& lifecycle);
  void Activate() override;
  void Deactivate() override;

 private:
  void Tick() override;
  void PublishMap();
  void PublishDiagnostics();
  // Subscribes `topic` for what ROS 2 tools send: a sample is refused (DropLog) unless dds.allow_writes, or when
  // `take` throws std::invalid_argument (a value that cannot be used).
  template <typename PubSubType>
  void TakeWrites(const std::string& topic, std::function<void(const typename PubSubType::type&)> take);
  // Throws std::invalid_argument unless the header names the map frame (or none: RViz's tools always do).
  static void RequireMapFrame(const std_msgs::msg::Header& header);

  drivers::dds::Participant& participant_;
  DdsOptions options_;
  RobotFrames frames_;
  const RobotCore& core_;
  const MapLibrary& maps_;
  const Lifecycle& lifecycle_;
  const drivers::dds::StampClock stamps_;

  template <typename T>
  using WriterOf = std::unique_ptr<drivers::dds::Writer<T>>;
  WriterOf<nav_msgs::msg::OdometryPubSubType> odom_;
  WriterOf<sensor_msgs::msg::BatteryStatePubSubType> battery_;
  WriterOf<tf2_msgs::msg::TFMessagePubSubType> tf_;
  WriterOf<tf2_msgs::msg::TFMessagePubSubType> tf_static_;
  WriterOf<sensor_msgs::msg::LaserScanPubSubType> scan_;
  WriterOf<nav_msgs::msg::OccupancyGridPubSubType> map_;
  WriterOf<nav_msgs::msg::PathPubSubType> plan_;
  WriterOf<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> pose_;
  WriterOf<diagnostic_msgs::msg::DiagnosticArrayPubSubType> diagnostics_;
  WriterOf<std_msgs::msg::StringPubSubType> state_;
  WriterOf<sensor_msgs::msg::ImagePubSubType> depth_;
  WriterOf<sensor_msgs::msg::CameraInfoPubSubType> camera_info_;
  std::vector<std::unique_ptr<drivers::dds::Subscription>> subscriptions_;
  std::vector<std::unique_ptr<drivers::dds::DropLog>> drops_;  // one per topic taken, for subscriptions_

  // On the bridge's executor only.
  std::string map_name_;
  std::uint64_t map_revision_ = 0;
  std::uint64_t mapping_revision_ = 0;
  std::vector<nav::Pose2> plan_path_;
  drivers::TimeNs next_depth_ns_ = 0;
  drivers::TimeNs next_map_odom_ns_ = 0;
  int ticks_ = 0;
};

}  // namespace corridor::server
