// The simulator's robot served as native devices (corridor-emulate, and tests that run corridord on native drivers
// in the simulated world): its base as an iRobot Create 2 and its laser as an RPLIDAR, each on a pseudo-terminal
// (testing/emulators), so that corridord configured for those devices drives the simulated robot through its native
// drivers, byte for byte as it would drive the real ones.
//
// The simulator runs in real time on a thread of its own, and paces both devices in its own time (Pace::kOwner): a
// machine too busy to keep the simulator up delays what the devices send, as a slow link would, but never makes them
// report a world other than the simulated one. The Create 2's wheel speeds, as corridord commands them, drive the
// simulated base (its encoders count those speeds over each physics step, as a real Create 2's count its wheels'
// turns: where the simulated body slips or is held, odometry and truth part, as on a real robot); the RPLIDAR's every
// sample is a beam cast as it is sent, from where the robot is then (a rotating laser's timing; the simulated laser
// sits at the base's centre: corridord's rplidar slot has no mounting offset); a bump in the simulator presses the
// Create 2's bumper; the simulated battery is the Create 2's.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include "drivers/laser2d.h"
#include "nav/geometry/pose2.h"
#include "server/app/simulator.h"
#include "server/config/config.h"
#include "testing/emulators/create2_emulator.h"
#include "testing/emulators/rplidar_emulator.h"

namespace corridor::testing {

class EmulatedRobot {
 public:
  // The simulator of `config` (its sim.* section: world, start, people), with its laser, serving a Create 2 on
  // `create2` and an RPLIDAR on `rplidar` (the paths where their pseudo-terminals are linked). Throws
  // std::runtime_error when the world cannot be loaded.
  EmulatedRobot(server::Config config, const std::filesystem::path& create2, const std::filesystem::path& rplidar);
  EmulatedRobot(const EmulatedRobot&) = delete;
  EmulatedRobot& operator=(const EmulatedRobot&) = delete;
  ~EmulatedRobot();

  // The simulated robot's true pose in the world. Thread-safe.
  nav::Pose2 true_pose() const;
  // Whether the simulated body has hit anything since the start. Thread-safe.
  bool bumped() const;
  Create2Emulator& base() { return *base_; }
  RplidarEmulator& laser() { return *laser_; }

 private:
  void Run(std::stop_token stop);
  double RangeAt(double clockwise_deg);  // the RPLIDAR's measurement, on the simulator's thread

  server::Simulator sim_;
  mutable std::mutex mutex_;  // guards bumped_
  bool bumped_ = false;
  std::unique_ptr<Create2Emulator> base_;
  std::unique_ptr<RplidarEmulator> laser_;
  std::jthread thread_;
};

}  // namespace corridor::testing
