// What the DDS interop test and the DDS benchmark share: a real corridord with DDS on loopback, and the robot's
// ROS 2 drivers played by a Cyclone DDS peer.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/dds/cyclone_peer.h"
#include "tests/dds/idl/std_msgs.h"

namespace corridor::testing {

std::string ReadFile(const std::filesystem::path& file);

// The tree's configuration (`source`/config/corridor.yaml) with DDS on loopback (unicast peers: loopback has no
// multicast) in `domain` (negative: DDS off), `extra` keys of the dds section (indented by two), and `devices`, the
// devices section's slots (indented by two) in place of the simulator's (empty: the simulator's robot), with the
// world's map as map.file and localization on odometry alone unless `laser_localization` (the devices' laser sees
// that world: corridor-emulate's). "" when the tree's file has changed shape.
std::string DdsConfig(const std::filesystem::path& source, int domain, bool allow_writes, const std::string& extra,
                      const std::string& devices = "", bool laser_localization = false);

// A corridord of its own (a fresh state directory, an admin API token), stopped with SIGTERM at the end. Throws
// std::runtime_error when it does not start within 30 s.
class DaemonProcess {
 public:
  DaemonProcess(const std::filesystem::path& corridord, const std::filesystem::path& source, int domain,
                bool allow_writes, const std::string& extra = "", const std::string& devices = "",
                bool laser_localization = false);
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;
  ~DaemonProcess();
  // Stops it (SIGTERM) and says whether it exited cleanly; idempotent.
  bool Stop();
  std::string log() const;
  int pid() const { return pid_; }
  int port() const { return port_; }
  const std::string& token() const { return token_; }
  // One HTTP request to its API on loopback with its admin token: the status and the JSON body (discarded when none).
  // Throws boost::system::system_error when it does not answer.
  std::pair<int, nlohmann::json> Call(const std::string& method, const std::string& target,
                                      const nlohmann::json& body = nullptr) const;

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
  int port_ = 0;
  std::string token_;
  bool exited_ok_ = false;
};

// A DDS Security keystore made by the tree's tools/dds-keystore in a directory of its own (named after `name` and the
// process), removed at the end. Throws std::runtime_error when the tool fails.
class Keystore {
 public:
  Keystore(const std::filesystem::path& source, const std::string& name);
  Keystore(const Keystore&) = delete;
  Keystore& operator=(const Keystore&) = delete;
  ~Keystore();
  // A new enclave's directory; `flags` as the tool takes them ("--read-only").
  std::string Enclave(const std::string& name, const std::string& flags = "");

 private:
  void Run(const std::string& args) const;
  std::filesystem::path tool_;
  std::filesystem::path dir_;
};

// A domain of this process's own, so that parallel runs never meet.
int Domain(int offset);

bool SendTwist(dds_entity_t writer, double linear, double angular);

// The latest state corridord published on /corridor/state.
struct StateWatch {
  nlohmann::json latest;
  void operator()(const std_msgs_msg_String& s);
};

// The robot's ROS 2 drivers, played by the peer on a thread of its own: a depth camera (camera info and 16UC1 images
// of a flat floor, 160 x 120 at 20 Hz), a laser (/scan, 20 Hz) and a differential base (odometry at 50 Hz from the last
// /cmd_vel, which it holds for 0.5 s, as diff_drive_controller's timeout does).
class RosDrivers {
 public:
  explicit RosDrivers(CyclonePeer& peer);
  RosDrivers(const RosDrivers&) = delete;
  RosDrivers& operator=(const RosDrivers&) = delete;
  ~RosDrivers();
  // The fastest forward command the base got, and the distance it drove.
  double fastest_command() const { return fastest_command_.load(); }
  double driven() const { return x_.load(); }
  // Sends one depth image in an encoding corridor must refuse.
  void SendBadImage();

 private:
  static constexpr int kWidth = 160;
  static constexpr int kHeight = 120;
  static constexpr double kF = 90.0;
  static constexpr double kCx = 79.5;
  static constexpr double kCy = 59.5;

  void Run();
  static builtin_interfaces_msg_Time Stamp();

  CyclonePeer& peer_;
  dds_entity_t info_;
  dds_entity_t depth_;
  dds_entity_t odom_;
  dds_entity_t scan_;
  dds_entity_t battery_;
  dds_entity_t cmd_vel_;
  std::vector<std::uint16_t> floor_;
  std::atomic<bool> stop_{false};
  std::atomic<double> fastest_command_{0.0};
  std::atomic<double> x_{0.0};
  std::thread thread_;
};

}  // namespace corridor::testing
