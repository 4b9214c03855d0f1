// Scans a rotating laser's driver hands on, checked against the room its emulator measures: for tests of the drivers
// of devices that report clockwise (RPLIDAR, LDS), whose scans must come out counter-clockwise (REP-103).
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <numbers>

#include "drivers/laser2d.h"

namespace corridor::testing {

class RoomScans {
 public:
  // `room`: the distance in metres at an angle clockwise from the device's forward (degrees).
  explicit RoomScans(std::function<double(double)> room) : room_(std::move(room)) {}

  // Takes every scan `laser` hands on from now (the laser must not outlive this).
  void Connect(drivers::Laser2D& laser) {
    laser.SetScanHandler([this](std::shared_ptr<const drivers::LaserScan> scan) { Take(*scan); });
  }

  void Take(const drivers::LaserScan& scan) {
    int bad = 0;
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      if (!std::isfinite(scan.ranges[i])) continue;
      // Counter-clockwise in the scan: the device's clockwise angle is its negative.
      const double ccw_deg = (scan.angle_min_rad + i * scan.angle_increment_rad) * 180.0 / std::numbers::pi;
      const double cw_deg = std::fmod(-ccw_deg + 720.0, 360.0);
      if (std::abs(scan.ranges[i] - room_(cw_deg)) > 1e-3) ++bad;
    }
    std::lock_guard lock(mutex_);
    ++scans_;
    wrong_ += bad;
  }
  int count() const {
    std::lock_guard lock(mutex_);
    return scans_;
  }
  // Beams so far whose range is not the room's at their angle.
  int wrong() const {
    std::lock_guard lock(mutex_);
    return wrong_;
  }

 private:
  std::function<double(double)> room_;
  mutable std::mutex mutex_;
  int scans_ = 0;
  int wrong_ = 0;
};

}  // namespace corridor::testing
