#include "tests/dds/ros2_fixtures.h"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "tests/dds/idl/geometry_msgs.h"
#include "tests/dds/idl/nav_msgs.h"
#include "tests/dds/idl/sensor_msgs.h"

namespace corridor::testing {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string ReadFile(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string DdsConfig(const fs::path& source, int domain, bool allow_writes, const std::string& extra,
                      const std::string& devices, bool laser_localization) {
  std::string config = ReadFile(source / "config/corridor.yaml");
  const std::size_t begin = config.find("\ndds:\n");
  const std::size_t end = config.find("\nlog:\n");
  if (begin == std::string::npos || end == std::string::npos) return "";
  std::string dds = "\ndds:\n  enabled: " + std::string(domain >= 0 ? "true" : "false") +
                    "\n  peers: [127.0.0.1]\n  interfaces: [lo]\n";
  dds += "  domain_id: " + std::to_string(std::max(domain, 0)) + "\n";
  dds += allow_writes ? "  allow_writes: true\n" : "  allow_writes: false\n";
  dds += extra;
  config.replace(begin, end - begin, dds);
  if (!devices.empty()) {
    // The devices section, whatever it holds, up to the simulator's that follows it.
    const std::size_t slots = config.find("\ndevices:\n");
    const std::size_t after = config.find("\nsim:\n", slots);
    if (slots == std::string::npos || after == std::string::npos) return "";
    config.replace(slots, after - slots, "\ndevices:\n" + devices + "\n");
    for (const auto& [from, to] :
         {std::pair<std::string, std::string>{"\n  source: mcl ",
                                              laser_localization ? "\n  source: mcl " : "\n  source: odometry "},
          {"\nmap:\n  file: \"\"", "\nmap:\n  file: \"worlds/willow_garage/willow-full-0.05.yaml\""}}) {
      const std::size_t at = config.find(from);
      if (at == std::string::npos) return "";
      config.replace(at, from.size(), to);
    }
  }
  // The config is written elsewhere: its relative paths must not be.
  for (std::size_t at = 0; (at = config.find("\"worlds/", at)) != std::string::npos;) {
    config.replace(at, 8, std::string("\"").append((source / "config/worlds/").string()));
    at += 8;
  }
  return config;
}

std::pair<int, nlohmann::json> DaemonProcess::Call(const std::string& method, const std::string& target,
                                                   const nlohmann::json& body) const {
  namespace http = boost::beast::http;
  boost::asio::io_context io;
  boost::beast::tcp_stream stream(io);
  boost::asio::ip::tcp::resolver resolver(io);
  stream.connect(resolver.resolve("127.0.0.1", std::to_string(port_)));
  http::request<http::string_body> request{http::string_to_verb(method), target, 11};
  request.set(http::field::host, "127.0.0.1");
  request.set(http::field::authorization, "Bearer " + token_);
  if (!body.is_null()) {
    request.set(http::field::content_type, "application/json");
    request.body() = body.dump();
  }
  request.prepare_payload();
  http::write(stream, request);
  boost::beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  return {response.result_int(), nlohmann::json::parse(response.body(), nullptr, false)};
}

DaemonProcess::DaemonProcess(const fs::path& corridord, const fs::path& source, int domain, bool allow_writes,
                             const std::string& extra, const std::string& devices, bool laser_localization) {
  dir_ = fs::temp_directory_path() / ("corridor-dds-" + std::to_string(::getpid()) + "-" + std::to_string(domain));
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  const std::string config = DdsConfig(source, domain, allow_writes, extra, devices, laser_localization);
  if (config.empty()) throw std::runtime_error("config/corridor.yaml has changed: cannot make the configuration");
  std::ofstream(dir_ / "corridor.yaml") << config;
  const std::string log_file = (dir_ / "corridord.log").string();
  const std::string config_file = (dir_ / "corridor.yaml").string();
  const std::string state = (dir_ / "state").string();
  // An API token for HTTP clients, minted offline as root does on the robot.
  const std::string mint =
      corridord.string() + " token create --role admin --name dds --state-dir " + state + " 2>/dev/null";
  if (FILE* pipe = ::popen(mint.c_str(), "r")) {
    char buffer[256] = {};
    if (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) token_ = buffer;
    ::pclose(pipe);
    while (!token_.empty() && (token_.back() == '\n' || token_.back() == ' ')) token_.pop_back();
  }
  pid_ = ::fork();
  if (pid_ == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // a test or bench killed half-way takes its daemon with it
    std::freopen(log_file.c_str(), "w", stderr);
    ::execl(corridord.c_str(), corridord.c_str(), "--config", config_file.c_str(), "--port", "0", "--state-dir",
            state.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const auto end = std::chrono::steady_clock::now() + 30s;
  while (std::chrono::steady_clock::now() < end) {
    const std::string text = log();
    const std::size_t at = text.find("listening on http://0.0.0.0:");
    if (at != std::string::npos) {
      port_ = std::atoi(text.c_str() + at + 28);
      return;
    }
    std::this_thread::sleep_for(50ms);
  }
  Stop();
  throw std::runtime_error("corridord did not start:\n" + log());
}

DaemonProcess::~DaemonProcess() {
  Stop();
  fs::remove_all(dir_);
}

bool DaemonProcess::Stop() {
  if (pid_ <= 0) return exited_ok_;
  ::kill(pid_, SIGTERM);
  int status = 0;
  ::waitpid(pid_, &status, 0);
  pid_ = -1;
  exited_ok_ = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return exited_ok_;
}

std::string DaemonProcess::log() const { return ReadFile(dir_ / "corridord.log"); }

Keystore::Keystore(const fs::path& source, const std::string& name)
    : tool_(source / "tools/dds-keystore"),
      dir_(fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
  fs::remove_all(dir_);
  Run("create " + dir_.string());
}

Keystore::~Keystore() { fs::remove_all(dir_); }

std::string Keystore::Enclave(const std::string& name, const std::string& flags) {
  Run("enclave " + dir_.string() + " " + name + " " + flags);
  return (dir_ / "enclaves" / name).string();
}

void Keystore::Run(const std::string& args) const {
  const std::string command = tool_.string() + " " + args + " >/dev/null";
  if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: dds-keystore " + args);
}

int Domain(int offset) { return 100 + (static_cast<int>(::getpid()) * 2 + offset) % 120; }

bool SendTwist(dds_entity_t writer, double linear, double angular) {
  geometry_msgs_msg_Twist twist{};
  twist.linear.x = linear;
  twist.angular.z = angular;
  return dds_write(writer, &twist) == DDS_RETCODE_OK;
}

void StateWatch::operator()(const std_msgs_msg_String& s) { latest = nlohmann::json::parse(s.data, nullptr, false); }

RosDrivers::RosDrivers(CyclonePeer& peer)
    : peer_(peer),
      info_(peer.Writer("/camera/depth/camera_info", sensor_msgs_msg_CameraInfo_desc)),
      depth_(peer.Writer("/camera/depth/image_rect_raw", sensor_msgs_msg_Image_desc)),
      odom_(peer.Writer("/odom", nav_msgs_msg_Odometry_desc)),
      scan_(peer.Writer("/scan", sensor_msgs_msg_LaserScan_desc)),
      battery_(peer.Writer("/battery_state", sensor_msgs_msg_BatteryState_desc)),
      cmd_vel_(peer.Reader("/cmd_vel", geometry_msgs_msg_Twist_desc)),
      floor_(kWidth * kHeight) {
  // The floor as a camera 0.3 m up, pitched down 10 degrees, sees it (depth along the optical axis, mm).
  const double tilt = 10.0 * M_PI / 180.0;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const double y = (v - kCy) / kF;  // the ray's downward slope in the optical frame, whatever its column
      const double down = y * std::cos(tilt) + std::sin(tilt);  // the ray's drop per metre of depth
      const double depth = down > 1e-3 ? 0.3 / down : 0.0;
      floor_[static_cast<std::size_t>(v * kWidth + u)] = depth < 6.0 ? static_cast<std::uint16_t>(depth * 1000.0) : 0;
    }
  }
  thread_ = std::thread([this] { Run(); });
}
RosDrivers::~RosDrivers() {
  stop_ = true;
  thread_.join();
}

void RosDrivers::SendBadImage() {
  std::vector<std::uint8_t> bytes(kWidth * kHeight * 3, 0);
  sensor_msgs_msg_Image image{};
  image.header.frame_id = const_cast<char*>("camera_depth_optical_frame");
  image.height = kHeight;
  image.width = kWidth;
  image.encoding = const_cast<char*>("rgb8");
  image.step = kWidth * 3;
  image.data._length = image.data._maximum = static_cast<std::uint32_t>(bytes.size());
  image.data._buffer = bytes.data();
  dds_write(depth_, &image);
}

void RosDrivers::Run() {
  using Clock = std::chrono::steady_clock;
  auto next_frame = Clock::now();
  auto next_battery = Clock::now();
  auto last = Clock::now();
  auto commanded = Clock::now() - 1s;
  double v = 0.0;
  double w = 0.0;
  double x = 0.0, y = 0.0, yaw = 0.0;
  while (!stop_) {
    peer_.Take<geometry_msgs_msg_Twist>(cmd_vel_, [&](const geometry_msgs_msg_Twist& t) {
      v = t.linear.x;
      w = t.angular.z;
      commanded = Clock::now();
      fastest_command_ = std::max(fastest_command_.load(), v);
    });
    const auto now = Clock::now();
    if (now - commanded > 500ms) v = w = 0.0;
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    x += v * std::cos(yaw) * dt;
    y += v * std::sin(yaw) * dt;
    yaw += w * dt;
    x_ = std::hypot(x, y);
    const auto stamp = Stamp();
    nav_msgs_msg_Odometry odom{};
    odom.header.stamp = stamp;
    odom.header.frame_id = const_cast<char*>("odom");
    odom.child_frame_id = const_cast<char*>("base_link");
    odom.pose.pose.position.x = x;
    odom.pose.pose.position.y = y;
    odom.pose.pose.orientation.z = std::sin(yaw / 2);
    odom.pose.pose.orientation.w = std::cos(yaw / 2);
    odom.twist.twist.linear.x = v;
    odom.twist.twist.angular.z = w;
    dds_write(odom_, &odom);
    if (now >= next_frame) {
      // A laser 2 m from a wall all round (180 beams), at the camera's rate.
      std::vector<float> ranges(180, 2.0f);
      sensor_msgs_msg_LaserScan scan{};
      scan.header.stamp = stamp;
      scan.header.frame_id = const_cast<char*>("laser");
      scan.angle_min = static_cast<float>(-M_PI);
      scan.angle_increment = static_cast<float>(2 * M_PI / 180);
      scan.angle_max = scan.angle_min + 179 * scan.angle_increment;
      scan.range_min = 0.1f;
      scan.range_max = 8.0f;
      scan.time_increment = 0.04f / 180;  // a laser turning once a frame, beam after beam
      scan.scan_time = 0.04f;
      scan.ranges._length = scan.ranges._maximum = 180;
      scan.ranges._buffer = ranges.data();
      dds_write(scan_, &scan);
      next_frame = now + 40ms;
      sensor_msgs_msg_CameraInfo info{};
      info.header.stamp = stamp;
      info.header.frame_id = const_cast<char*>("camera_depth_optical_frame");
      info.width = kWidth;
      info.height = kHeight;
      info.distortion_model = const_cast<char*>("plumb_bob");
      const double k[9] = {kF, 0, kCx, 0, kF, kCy, 0, 0, 1};
      std::copy(k, k + 9, info.k);
      dds_write(info_, &info);
      sensor_msgs_msg_Image image{};
      image.header = info.header;
      image.height = kHeight;
      image.width = kWidth;
      image.encoding = const_cast<char*>("16UC1");
      image.step = kWidth * 2;
      image.data._length = image.data._maximum = kWidth * kHeight * 2;
      image.data._buffer = reinterpret_cast<std::uint8_t*>(floor_.data());
      dds_write(depth_, &image);
    }
    if (now >= next_battery) {
      // A base driver's battery, once a second: 42 %, discharging.
      sensor_msgs_msg_BatteryState battery{};
      battery.header.stamp = stamp;
      battery.header.frame_id = const_cast<char*>("base_link");
      battery.voltage = 12.1f;
      battery.current = -0.8f;
      battery.percentage = 0.42f;
      battery.power_supply_status = 2;
      battery.present = true;
      battery.location = const_cast<char*>("");
      battery.serial_number = const_cast<char*>("");
      dds_write(battery_, &battery);
      next_battery = now + 1s;
    }
    std::this_thread::sleep_for(20ms);
  }
}
builtin_interfaces_msg_Time RosDrivers::Stamp() {
  const auto ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  return {static_cast<std::int32_t>(ns / 1000000000), static_cast<std::uint32_t>(ns % 1000000000)};
}

}  // namespace corridor::testing
