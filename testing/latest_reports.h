// The newest odometry and battery report a base driver handed on, for tests of the native base drivers: their
// handlers run on the driver's thread, the test reads from its own.
#pragma once

#include <mutex>
#include <optional>

#include "drivers/battery.h"
#include "drivers/diff_drive_base.h"

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
  std::optional<drivers::BatteryState> Battery() {
    std::lock_guard lock(mutex);
    return battery;
  }
};

}  // namespace corridor::testing
