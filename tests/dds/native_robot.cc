#include "tests/dds/native_robot.h"

#include <thread>

namespace corridor::testing {

using namespace std::chrono_literals;

NativeRobot::NativeRobot(const std::filesystem::path& corridord, const std::filesystem::path& source, int domain)
    : dir_(std::filesystem::temp_directory_path() /
           ("corridor-native-" + std::to_string(::getpid()) + "-" + std::to_string(domain))) {
  std::filesystem::create_directories(dir_);
  base_ = std::make_unique<Create2Emulator>(dir_ / "create2");
  laser_ = std::make_unique<RplidarEmulator>(dir_ / "rplidar", RplidarEmulatorOptions{});
  peer_ = std::make_unique<CyclonePeer>(domain);
  camera_ = std::make_unique<RosDrivers>(*peer_);  // before corridord: it waits for the camera's info
  const std::string devices =
      "  base: {driver: create2, port: " + (dir_ / "create2").string() +
      "}\n"
      "  laser: {driver: rplidar, port: " +
      (dir_ / "rplidar").string() +
      ", mount_yaw_deg: 180}\n"
      "  camera: {driver: dds, depth_topic: /camera/depth/image_rect_raw, info_topic: /camera/depth/camera_info}\n";
  daemon_ = std::make_unique<DaemonProcess>(corridord, source, domain, /*allow_writes=*/false, "", devices);
}

NativeRobot::~NativeRobot() {
  daemon_.reset();
  camera_.reset();
  peer_.reset();
  laser_.reset();
  base_.reset();
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

bool NativeRobot::Until(bool drive, std::chrono::milliseconds deadline, const std::function<bool()>& done) {
  const auto end = std::chrono::steady_clock::now() + deadline;
  while (std::chrono::steady_clock::now() < end) {
    if (drive) daemon_->Call("POST", "/api/v1/teleop", {{"linear_mps", 0.2}, {"angular_rps", 0.0}});
    if (done()) return true;
    std::this_thread::sleep_for(100ms);  // the teleop rate, not a wait for anything
  }
  return done();
}

bool NativeRobot::moving() const {
  const auto [left, right] = base_->wheels_mmps();
  return left > 100 && right > 100;
}

bool NativeRobot::still() const { return base_->wheels_mmps() == std::pair<int, int>{0, 0}; }

std::string NativeRobot::DeviceState(const std::string& device) {
  const auto [status, body] = daemon_->Call("GET", "/api/v1/devices");
  if (status != 200) return "";
  for (const nlohmann::json& d : body["devices"]) {
    if (d["device"] == device) return d["state"].get<std::string>();
  }
  return "";
}

bool NativeRobot::AllOk() {
  for (const char* device : {"base", "laser", "camera"}) {
    if (DeviceState(device) != "ok") return false;
  }
  return true;
}

double NativeRobot::Rate(const std::string& device) {
  const auto [status, body] = daemon_->Call("GET", "/api/v1/devices");
  if (status != 200) return 0.0;
  for (const nlohmann::json& d : body["devices"]) {
    if (d["device"] == device) return d["rate_hz"].get<double>();
  }
  return 0.0;
}

}  // namespace corridor::testing
