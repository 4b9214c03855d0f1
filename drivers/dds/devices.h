// Devices served by ROS 2 drivers over DDS (realsense2_camera, a laser driver, a base's diff_drive_controller), as
// corridor's DepthCamera, Laser2D and DiffDriveBase: corridor then runs on a robot whose hardware ROS 2 already
// drives. What arrives is checked like any input: a sample that cannot be used is dropped with a warning (rate
// limited) and counted; a device that stops sending simply stops delivering, which the graph's watchdogs see (the
// command gate stops the robot when depth frames or odometry stop).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "drivers/battery.h"
#include "drivers/dds/device_options.h"
#include "drivers/dds/participant.h"
#include "drivers/dds/ros2_convert.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "ros2/geometry_msgsPubSubTypes.h"
#include "ros2/nav_msgsPubSubTypes.h"
#include "ros2/sensor_msgsPubSubTypes.h"

namespace corridor::drivers::dds {

// A handler installed from one thread and called from DDS's: copied out under the lock, called outside it.
template <typename Handler>
class HandlerSlot {
 public:
  void Set(Handler handler) {
    std::lock_guard lock(mutex_);
    handler_ = std::move(handler);
  }
  Handler Get() const {
    std::lock_guard lock(mutex_);
    return handler_;
  }

 private:
  mutable std::mutex mutex_;
  Handler handler_;
};

class DdsDepthCamera final : public DepthCamera {
 public:
  // Subscribes at once; info() is valid after WaitForInfo. `clock`: the host's, to stamp arrivals and convert stamps.
  DdsDepthCamera(Participant& participant, const DdsCameraOptions& options, const Clock& clock);
  // Waits for the first CameraInfo; throws std::runtime_error naming the topic when none came within `timeout`.
  void WaitForInfo(std::chrono::milliseconds timeout);
  CameraInfo info() const override;
  void SetFrameHandler(FrameHandler handler) override;
  // Ends the subscriptions (waiting for a delivery in progress): the handler is not called after it. Idempotent.
  void Stop();

 private:
  void Depth(const sensor_msgs::msg::Image& image);

  DdsCameraOptions options_;
  const StampClock stamps_;
  DropLog drops_{"camera"};
  mutable std::mutex mutex_;
  std::condition_variable info_arrived_;
  std::optional<CameraInfo> info_;  // guarded by mutex_
  cv::Mat color_;                   // the latest colour image (guarded by mutex_)
  HandlerSlot<FrameHandler> handler_;
  std::uint64_t sequence_ = 0;
  std::unique_ptr<Subscription> info_subscription_;
  std::unique_ptr<Subscription> color_subscription_;
  std::unique_ptr<Subscription> depth_subscription_;
};

class DdsLaser final : public Laser2D {
 public:
  DdsLaser(Participant& participant, const DdsLaserOptions& options, const Clock& clock);
  nav::Pose2 base_T_laser() const override { return options_.base_T_laser; }
  double height_m() const override { return options_.height_m; }
  void SetScanHandler(ScanHandler handler) override;
  void Stop() { subscription_.reset(); }  // as DdsDepthCamera::Stop

 private:
  DdsLaserOptions options_;
  const StampClock stamps_;
  DropLog drops_{"laser"};
  HandlerSlot<ScanHandler> handler_;
  std::unique_ptr<Subscription> subscription_;
};

// A base driven by its ROS 2 driver: odometry in, velocity out, and its battery when options.battery_topic names it
// (a Battery only then: has_battery()).
class DdsBase final : public DiffDriveBase, public Battery {
 public:
  DdsBase(Participant& participant, const DdsBaseOptions& options, const Clock& clock);
  BaseLimits limits() const override { return options_.limits; }
  // Clamped to the limits and sent as a Twist; the base driver's own command timeout stops it when they stop.
  void SetVelocity(const nav::Twist2& command) override;
  void SetOdometryHandler(OdometryHandler handler) override;
  bool has_battery() const { return battery_subscription_ != nullptr; }
  void SetBatteryHandler(BatteryHandler handler) override;
  void Stop() {  // as DdsDepthCamera::Stop
    subscription_.reset();
    battery_subscription_.reset();
  }

 private:
  DdsBaseOptions options_;
  const StampClock stamps_;
  DropLog drops_{"base"};
  HandlerSlot<OdometryHandler> handler_;
  HandlerSlot<BatteryHandler> battery_handler_;
  std::unique_ptr<Writer<geometry_msgs::msg::TwistPubSubType>> cmd_vel_;
  std::unique_ptr<Subscription> subscription_;
  std::unique_ptr<Subscription> battery_subscription_;
};

}  // namespace corridor::drivers::dds
