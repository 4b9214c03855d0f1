// corridor-emulate: the simulator's robot served as native devices on pseudo-terminals (testing/emulated_robot.h):
// its base as an iRobot Create 2 and its laser as an RPLIDAR. Start it, then corridord with devices.base a create2
// and devices.laser an rplidar on the paths given here, devices.camera none, and the world's map as map.file: the
// daemon then drives the simulated robot through its native drivers, as it would drive the real devices.
#include <signal.h>

#include <cstdio>
#include <iostream>
#include <string>

#include <spdlog/spdlog.h>

#include "server/config/config.h"
#include "testing/emulated_robot.h"

namespace {

constexpr const char* kUsage = R"(usage: corridor-emulate --config FILE --create2 PATH --rplidar PATH

Runs the simulator of FILE's sim section (world, start, people) in real time and serves its robot as an iRobot
Create 2 (Open Interface, on a pseudo-terminal linked at --create2) and an RPLIDAR (standard scans, linked at
--rplidar), until interrupted. Configure corridord with, e.g.:
  devices:
    base:   {driver: create2, port: PATH}
    laser:  {driver: rplidar, port: PATH}
    camera: {driver: none}
  map: {file: <the world's map>}
)";

}  // namespace

int main(int argc, char** argv) {
  std::string config_file;
  std::string create2;
  std::string rplidar;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (i + 1 >= argc) {
      std::cerr << arg << ": needs a value\n" << kUsage;
      return 2;
    }
    const std::string value = argv[++i];
    if (arg == "--config") {
      config_file = value;
    } else if (arg == "--create2") {
      create2 = value;
    } else if (arg == "--rplidar") {
      rplidar = value;
    } else {
      std::cerr << arg << ": unknown option\n" << kUsage;
      return 2;
    }
  }
  if (config_file.empty() || create2.empty() || rplidar.empty()) {
    std::cerr << "--config, --create2 and --rplidar are all required\n" << kUsage;
    return 2;
  }
  // Interrupts are taken by sigwait below, not by a handler: block them before any thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  try {
    const corridor::server::Config config = corridor::server::LoadConfig(config_file);
    corridor::testing::EmulatedRobot robot(config, create2, rplidar);
    spdlog::info("corridor-emulate: a Create 2 on {}, an RPLIDAR on {}", create2, rplidar);
    int signal = 0;
    sigwait(&signals, &signal);
    const corridor::nav::Pose2 pose = robot.true_pose();
    spdlog::info("corridor-emulate: stopped with the robot at ({:.2f}, {:.2f}, {:.0f} deg){}", pose.x_m, pose.y_m,
                 pose.yaw_rad * 180.0 / 3.14159265358979, robot.bumped() ? ", having bumped into something" : "");
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "corridor-emulate: " << e.what() << "\n";
    return 1;
  }
}
