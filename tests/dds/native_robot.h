// A robot on native drivers for corridord, as tests and benchmarks drive it: a Create 2 and an RPLIDAR played by their
// emulators (testing/emulators) on pseudo-terminals, a depth camera over DDS played by a Cyclone peer (RosDrivers'
// camera; its base and laser are not listened to), and corridord from this build configured for them.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "testing/emulators/create2_emulator.h"
#include "testing/emulators/rplidar_emulator.h"
#include "tests/dds/ros2_fixtures.h"

namespace corridor::testing {

class NativeRobot {
 public:
  // `domain`: a DDS domain of the caller's own (Domain()). Throws std::runtime_error when corridord does not start.
  NativeRobot(const std::filesystem::path& corridord, const std::filesystem::path& source, int domain);
  NativeRobot(const NativeRobot&) = delete;
  NativeRobot& operator=(const NativeRobot&) = delete;
  ~NativeRobot();

  Create2Emulator& base() { return *base_; }
  RplidarEmulator& laser() { return *laser_; }
  DaemonProcess& daemon() { return *daemon_; }

  // Polls `done` until it holds or `deadline` passes, driving forward at 0.2 m/s through teleop meanwhile (10 Hz, as
  // a joystick does) when `drive`.
  bool Until(bool drive, std::chrono::milliseconds deadline, const std::function<bool()>& done);
  // Both wheels turning forward faster than 0.1 m/s; both stopped.
  bool moving() const;
  bool still() const;
  // The device's state in GET /api/v1/devices ("" when there is none); every device ok.
  std::string DeviceState(const std::string& device);
  bool AllOk();
  double Rate(const std::string& device);  // its rate_hz, 0 when there is none

 private:
  std::filesystem::path dir_;
  std::unique_ptr<Create2Emulator> base_;
  std::unique_ptr<RplidarEmulator> laser_;
  std::unique_ptr<CyclonePeer> peer_;
  std::unique_ptr<RosDrivers> camera_;
  std::unique_ptr<DaemonProcess> daemon_;
};

}  // namespace corridor::testing
