// The newest odometry and battery report a base driver handed on, for tests of the native base drivers: their
// handlers run on the driver's thread, the test reads from its own.
#pragma once

#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>

#include "drivers/battery.h"
#include "drivers/diff_drive_base.h"
#include "testing/eventually.h"

namespace corridor::testing {

struct LatestReports {
  std::mutex mutex;
  std::optional<drivers::WheelOdometry> odometry;
  std::optional<drivers::BatteryState> battery;

  template <typename Base>
  void Connect(Base& base) {
    base.SetOdometryHandler([this](const drivers::WheelOdometry& o) {
      std::lock_guard lock(mutex);
      odometry = o;
    });
    base.SetBatteryHandler([this](const drivers::BatteryState& b) {
      std::lock_guard lock(mutex);
      battery = b;
    });
  }
  drivers::WheelOdometry Odometry() {
    std::lock_guard lock(mutex);
    return odometry.value_or(drivers::WheelOdometry{});
  }
  // Whether the odometry's velocity comes within `tolerance` of (linear_mps, angular_rps) before `timeout`. Waited
  // for, not sampled once: on a busy host a reply may come past the driver's stale_s, and the driver then stops the
  // wheels and ramps them up again.
  bool VelocityReaches(double linear_mps, double angular_rps, double tolerance,
                       std::chrono::milliseconds timeout = std::chrono::milliseconds(2000)) {
    return Eventually(
        [&] {
          const nav::Twist2 v = Odometry().velocity;
          return std::abs(v.linear_mps - linear_mps) < tolerance && std::abs(v.angular_rps - angular_rps) < tolerance;
        },
        timeout);
  }
  std::optional<drivers::BatteryState> Battery() {
    std::lock_guard lock(mutex);
    return battery;
  }
};

}  // namespace corridor::testing
