#include "drivers/dds/devices.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <numbers>

#include "nav/geometry/camera_model.h"

namespace corridor::drivers::dds {
DdsDepthCamera::DdsDepthCamera(Participant& participant, const DdsCameraOptions& options, const Clock& clock)
    : options_(options), stamps_(StampClock::For(clock)) {
  info_subscription_ = participant.Subscribe<sensor_msgs::msg::CameraInfoPubSubType>(
      options_.info_topic, Qos::kSensor, [this](const sensor_msgs::msg::CameraInfo& message) {
        try {
          CameraInfo info;
          info.camera = FromRos(message, nav::CameraMount(options_.mount_x_m, options_.mount_height_m,
                                                          options_.tilt_deg * std::numbers::pi / 180.0));
          info.min_range_m = options_.min_range_m;
          info.max_range_m = options_.max_range_m;
          std::lock_guard lock(mutex_);
          if (info_ && (info_->camera.width != info.camera.width || info_->camera.height != info.camera.height)) {
            return drops_.Drop("the camera info's size changed while running; restart corridord to take it");
          }
          if (!info_) {
            info_ = info;
            info_arrived_.notify_all();
          }
        } catch (const std::invalid_argument& e) {
          drops_.Drop(e.what());
        }
      });
  if (!options_.color_topic.empty()) {
    color_subscription_ = participant.Subscribe<sensor_msgs::msg::ImagePubSubType>(
        options_.color_topic, Qos::kSensor, [this](const sensor_msgs::msg::Image& image) {
          try {
            cv::Mat color = ColorFromRos(image);
            std::lock_guard lock(mutex_);
            color_ = std::move(color);
          } catch (const std::invalid_argument& e) {
            drops_.Drop(e.what());
          }
        });
  }
  depth_subscription_ = participant.Subscribe<sensor_msgs::msg::ImagePubSubType>(
      options_.depth_topic, Qos::kSensor, [this](const sensor_msgs::msg::Image& image) { Depth(image); });
}

void DdsDepthCamera::WaitForInfo(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (!info_arrived_.wait_for(lock, timeout, [this] { return info_.has_value(); })) {
    throw std::runtime_error("dds camera: no usable sensor_msgs/CameraInfo on " + options_.info_topic + " within " +
                             std::to_string(timeout.count() / 1000.0) + " s (is the camera driver running, on the " +
                             "same ROS_DOMAIN_ID?)");
  }
}

CameraInfo DdsDepthCamera::info() const {
  std::lock_guard lock(mutex_);
  return info_.value_or(CameraInfo{});
}

void DdsDepthCamera::Stop() {
  depth_subscription_.reset();
  color_subscription_.reset();
  info_subscription_.reset();
}

void DdsDepthCamera::SetFrameHandler(FrameHandler handler) { handler_.Set(std::move(handler)); }

void DdsDepthCamera::Depth(const sensor_msgs::msg::Image& image) {
  auto frame = std::make_shared<RgbdFrame>();
  try {
    frame->depth_mm = DepthFromRos(image);
  } catch (const std::invalid_argument& e) {
    return drops_.Drop(e.what());
  }
  frame->stamp_ns = stamps_.FromRos(image.header().stamp());
  {
    std::lock_guard lock(mutex_);
    if (!info_) return drops_.Drop("a depth image before any camera info");
    if (frame->depth_mm.cols != info_->camera.width || frame->depth_mm.rows != info_->camera.height) {
      return drops_.Drop("the depth image's size is not the camera info's");
    }
    frame->color_bgr =
        color_.size() == frame->depth_mm.size() ? color_ : cv::Mat(frame->depth_mm.size(), CV_8UC3, cv::Scalar::all(0));
    frame->sequence = ++sequence_;
  }
  if (const FrameHandler handler = handler_.Get()) handler(std::move(frame));
}

DdsLaser::DdsLaser(Participant& participant, const DdsLaserOptions& options, const Clock& clock)
    : options_(options), stamps_(StampClock::For(clock)) {
  subscription_ = participant.Subscribe<sensor_msgs::msg::LaserScanPubSubType>(
      options_.topic, Qos::kSensor, [this](const sensor_msgs::msg::LaserScan& message) {
        std::shared_ptr<const LaserScan> scan;
        try {
          scan = std::make_shared<const LaserScan>(FromRos(message, stamps_));
        } catch (const std::invalid_argument& e) {
          return drops_.Drop(e.what());
        }
        if (const ScanHandler handler = handler_.Get()) handler(scan);
      });
}

void DdsLaser::SetScanHandler(ScanHandler handler) { handler_.Set(std::move(handler)); }

DdsBase::DdsBase(Participant& participant, const DdsBaseOptions& options, const Clock& clock)
    : options_(options), stamps_(StampClock::For(clock)) {
  cmd_vel_ = participant.Advertise<geometry_msgs::msg::TwistPubSubType>(options_.cmd_vel_topic, Qos::kDefault);
  subscription_ = participant.Subscribe<nav_msgs::msg::OdometryPubSubType>(
      options_.odom_topic, Qos::kSensor, [this](const nav_msgs::msg::Odometry& message) {
        WheelOdometry odometry;
        try {
          odometry = FromRos(message, stamps_);
        } catch (const std::invalid_argument& e) {
          return drops_.Drop(e.what());
        }
        if (const OdometryHandler handler = handler_.Get()) handler(odometry);
      });
  if (options_.battery_topic.empty()) return;
  battery_subscription_ = participant.Subscribe<sensor_msgs::msg::BatteryStatePubSubType>(
      options_.battery_topic, Qos::kSensor, [this](const sensor_msgs::msg::BatteryState& message) {
        BatteryState battery;
        try {
          battery = FromRos(message, stamps_);
        } catch (const std::invalid_argument& e) {
          return drops_.Drop(e.what());
        }
        if (const BatteryHandler handler = battery_handler_.Get()) handler(battery);
      });
}

void DdsBase::SetBatteryHandler(BatteryHandler handler) { battery_handler_.Set(std::move(handler)); }

void DdsBase::SetVelocity(const nav::Twist2& command) {
  const BaseLimits& l = options_.limits;
  cmd_vel_->Write(ToRos(nav::Twist2{std::clamp(command.linear_mps, -l.max_linear_mps, l.max_linear_mps),
                                    std::clamp(command.angular_rps, -l.max_angular_rps, l.max_angular_rps)}));
}

void DdsBase::SetOdometryHandler(OdometryHandler handler) { handler_.Set(std::move(handler)); }

}  // namespace corridor::drivers::dds
