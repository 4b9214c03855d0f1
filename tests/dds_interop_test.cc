// corridord as ROS 2 tools and drivers see it, checked with a second DDS vendor: a Cyclone DDS peer
// (tests/dds/cyclone_peer.h) on loopback receives /odom, /tf, /map and corridor's state from the real daemon running
// the simulator, drives the robot with /cmd_vel and sees it move, sends RViz's /goal_pose and sees the mission
// succeed; with writes off, sees /cmd_vel refused; and, with the simulator off, plays the robot's ROS 2 drivers (a
// depth camera and a base) that corridord runs on.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <set>
#include <string>

#include "tests/dds/cyclone_peer.h"
#include "tests/dds/idl/geometry_msgs.h"
#include "tests/dds/idl/nav_msgs.h"
#include "tests/dds/idl/sensor_msgs.h"
#include "tests/dds/idl/std_msgs.h"
#include "tests/dds/idl/tf2_msgs.h"

namespace corridor::testing {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string ReadFile(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The tree's configuration with DDS on loopback (unicast peers: loopback has no multicast) in `domain`; with
// `devices`, the simulator off and the robot's devices over DDS (`devices` is the dds.devices section).
std::string DdsConfig(int domain, bool allow_writes, const std::string& devices = "") {
  const fs::path source = CORRIDOR_SOURCE_DIR;
  std::string config = ReadFile(source / "config/corridor.yaml");
  const std::size_t begin = config.find("\ndds:\n");
  const std::size_t end = config.find("\nlog:\n");
  if (begin == std::string::npos || end == std::string::npos) return "";
  std::string dds = "\ndds:\n  enabled: true\n  peers: [127.0.0.1]\n  interfaces: [lo]\n";
  dds += "  domain_id: " + std::to_string(domain) + "\n";
  dds += allow_writes ? "  allow_writes: true\n" : "  allow_writes: false\n";
  dds += devices;
  config.replace(begin, end - begin, dds);
  if (!devices.empty()) {
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"\nsim:\n  enabled: true\n", "\nsim:\n  enabled: false\n"},
                                   {"\n  source: mcl ", "\n  source: odometry "},
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

// A corridord of its own (the simulator, a fresh state directory), stopped with SIGTERM at the end.
class Daemon {
 public:
  Daemon(int domain, bool allow_writes, const std::string& devices = "") {
    dir_ = fs::temp_directory_path() / ("corridor-dds-" + std::to_string(::getpid()) + "-" + std::to_string(domain));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string config = DdsConfig(domain, allow_writes, devices);
    EXPECT_FALSE(config.empty()) << "config/corridor.yaml has changed: the test cannot make its configuration";
    std::ofstream(dir_ / "corridor.yaml") << config;
    const std::string log = (dir_ / "corridord.log").string();
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string config_file = (dir_ / "corridor.yaml").string();
      const std::string state = (dir_ / "state").string();
      std::freopen(log.c_str(), "w", stderr);
      ::execl(CORRIDORD, CORRIDORD, "--config", config_file.c_str(), "--port", "0", "--state-dir", state.c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    const auto end = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < end && ReadFile(log).find("listening on") == std::string::npos) {
      std::this_thread::sleep_for(50ms);
    }
    EXPECT_NE(ReadFile(log).find("listening on"), std::string::npos) << ReadFile(log);
  }
  ~Daemon() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log();
    fs::remove_all(dir_);
  }
  std::string log() const { return ReadFile(dir_ / "corridord.log"); }

 private:
  fs::path dir_;
  pid_t pid_ = -1;
};

// A domain of this test process's own, so that parallel runs never meet.
int Domain(int offset) { return 100 + (static_cast<int>(::getpid()) * 2 + offset) % 120; }

void SendTwist(dds_entity_t writer, double linear, double angular) {
  geometry_msgs_msg_Twist twist{};
  twist.linear.x = linear;
  twist.angular.z = angular;
  const dds_return_t rc = dds_write(writer, &twist);
  EXPECT_EQ(rc, DDS_RETCODE_OK) << dds_strretcode(rc);
}

// The latest state corridord published on /corridor/state.
struct StateWatch {
  nlohmann::json latest;
  void operator()(const std_msgs_msg_String& s) { latest = nlohmann::json::parse(s.data, nullptr, false); }
};

TEST(DdsInterop, RosToolSeesTheRobotDrivesItAndSendsAGoal) {
  const int domain = Domain(0);
  Daemon daemon(domain, /*allow_writes=*/true);
  CyclonePeer peer(domain);
  const dds_entity_t map = peer.Reader("/map", nav_msgs_msg_OccupancyGrid_desc, PeerQos::kLatched);
  const dds_entity_t odom = peer.Reader("/odom", nav_msgs_msg_Odometry_desc);
  const dds_entity_t tf = peer.Reader("/tf", tf2_msgs_msg_TFMessage_desc, PeerQos::kTf);
  const dds_entity_t tf_static = peer.Reader("/tf_static", tf2_msgs_msg_TFMessage_desc, PeerQos::kLatched);
  const dds_entity_t state = peer.Reader("/corridor/state", std_msgs_msg_String_desc);
  const dds_entity_t cmd_vel = peer.Writer("/cmd_vel", geometry_msgs_msg_Twist_desc);
  const dds_entity_t goal_pose = peer.Writer("/goal_pose", geometry_msgs_msg_PoseStamped_desc);

  // The map, latched: the bundled Willow Garage map at 5 cm.
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::size_t cells = 0;
  std::string map_frame;
  ASSERT_TRUE(peer.TakeUntil<nav_msgs_msg_OccupancyGrid>(
      map,
      [&](const nav_msgs_msg_OccupancyGrid& m) {
        width = m.info.width;
        height = m.info.height;
        cells = m.data._length;
        map_frame = m.header.frame_id;
        EXPECT_NEAR(m.info.resolution, 0.05, 1e-6);
      },
      [&] { return cells > 0; }, 20s))
      << daemon.log();
  EXPECT_EQ(map_frame, "map");
  EXPECT_EQ(cells, static_cast<std::size_t>(width) * height);
  EXPECT_GT(width, 1000u);

  // Odometry and the transform tree: map -> odom -> base_link, and base_link -> the camera.
  int odometry = 0;
  ASSERT_TRUE(peer.TakeUntil<nav_msgs_msg_Odometry>(
      odom,
      [&](const nav_msgs_msg_Odometry& o) {
        ++odometry;
        EXPECT_STREQ(o.header.frame_id, "odom");
        EXPECT_STREQ(o.child_frame_id, "base_link");
      },
      [&] { return odometry >= 10; }, 10s));
  std::set<std::string> edges;
  peer.TakeUntil<tf2_msgs_msg_TFMessage>(
      tf,
      [&](const tf2_msgs_msg_TFMessage& m) {
        for (std::uint32_t i = 0; i < m.transforms._length; ++i) {
          edges.insert(std::string(m.transforms._buffer[i].header.frame_id) + "->" +
                       m.transforms._buffer[i].child_frame_id);
        }
      },
      [&] { return edges.contains("map->odom") && edges.contains("odom->base_link"); }, 10s);
  EXPECT_TRUE(edges.contains("map->odom"));
  EXPECT_TRUE(edges.contains("odom->base_link"));
  std::set<std::string> statics;
  peer.TakeUntil<tf2_msgs_msg_TFMessage>(
      tf_static,
      [&](const tf2_msgs_msg_TFMessage& m) {
        for (std::uint32_t i = 0; i < m.transforms._length; ++i) statics.insert(m.transforms._buffer[i].child_frame_id);
      },
      [&] { return statics.contains("camera_depth_optical_frame"); }, 5s);
  EXPECT_TRUE(statics.contains("camera_depth_optical_frame"));

  // Drive ahead with /cmd_vel (the corridor in front of the start is 11 m long) and see odometry follow.
  ASSERT_TRUE(peer.TakeUntil<nav_msgs_msg_Odometry>(
      odom, [](const auto&) {}, [&] { return peer.Matched(cmd_vel) > 0; }, 10s));
  nav_msgs_msg_Odometry last{};
  peer.Take<nav_msgs_msg_Odometry>(odom, [&](const nav_msgs_msg_Odometry& o) { last = o; });
  const double x0 = last.pose.pose.position.x;
  const double y0 = last.pose.pose.position.y;
  double moved = 0.0;
  double fastest = 0.0;
  for (int i = 0; i < 25; ++i) {  // 2.5 s at 10 Hz, as teleop_twist_keyboard sends
    SendTwist(cmd_vel, 0.3, 0.0);
    peer.Take<nav_msgs_msg_Odometry>(odom, [&](const nav_msgs_msg_Odometry& o) {
      moved = std::hypot(o.pose.pose.position.x - x0, o.pose.pose.position.y - y0);
      fastest = std::max(fastest, o.twist.twist.linear.x);
    });
    std::this_thread::sleep_for(100ms);
  }
  SendTwist(cmd_vel, 0.0, 0.0);
  EXPECT_GT(moved, 0.3) << "odometry moved " << moved << " m";
  EXPECT_NEAR(fastest, 0.3, 0.05);

  // RViz's 2D Goal Pose: 2 m further down the corridor, in the map frame; the mission must succeed.
  StateWatch watch;
  ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch), [&] { return watch.latest.contains("pose") && !watch.latest["pose"].is_null(); }, 10s));
  const double gx = watch.latest["pose"]["x"].get<double>();
  const double gy = watch.latest["pose"]["y"].get<double>() + 2.0;
  geometry_msgs_msg_PoseStamped goal{};
  goal.header.frame_id = const_cast<char*>("map");
  goal.pose.position.x = gx;
  goal.pose.position.y = gy;
  goal.pose.orientation.z = std::sin(M_PI / 4);
  goal.pose.orientation.w = std::cos(M_PI / 4);
  ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch), [&] { return peer.Matched(goal_pose) > 0; }, 10s));
  ASSERT_EQ(dds_write(goal_pose, &goal), DDS_RETCODE_OK);
  std::string status;
  const bool done = peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch),
      [&] {
        const auto& mission = watch.latest["mission"];
        status = mission.is_object() ? mission.value("status", "") : "";
        return status == "succeeded" || status == "failed" || status == "cancelled";
      },
      60s);
  EXPECT_TRUE(done) << "mission " << status << "\n" << daemon.log();
  EXPECT_EQ(status, "succeeded") << watch.latest.dump();
  EXPECT_NEAR(watch.latest["pose"]["x"].get<double>(), gx, 0.3);
  EXPECT_NEAR(watch.latest["pose"]["y"].get<double>(), gy, 0.3);
}

TEST(DdsInterop, WritesAreRefusedUnlessAllowed) {
  const int domain = Domain(1);
  Daemon daemon(domain, /*allow_writes=*/false);
  CyclonePeer peer(domain);
  const dds_entity_t odom = peer.Reader("/odom", nav_msgs_msg_Odometry_desc);
  const dds_entity_t cmd_vel = peer.Writer("/cmd_vel", geometry_msgs_msg_Twist_desc);
  ASSERT_TRUE(peer.TakeUntil<nav_msgs_msg_Odometry>(
      odom, [](const auto&) {}, [&] { return peer.Matched(cmd_vel) > 0; }, 20s))
      << daemon.log();
  double fastest = 0.0;
  for (int i = 0; i < 15; ++i) {
    SendTwist(cmd_vel, 0.3, 0.0);
    peer.Take<nav_msgs_msg_Odometry>(odom, [&](const nav_msgs_msg_Odometry& o) {
      fastest = std::max(fastest, std::abs(o.twist.twist.linear.x));
    });
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_LT(fastest, 0.01);
  EXPECT_NE(daemon.log().find("writes over DDS are off"), std::string::npos) << daemon.log();
}

// The robot's ROS 2 drivers, played by the peer on a thread of its own: a depth camera (camera info and 16UC1 images
// of a flat floor, 160 x 120 at 10 Hz) and a differential base (odometry at 50 Hz from the last /cmd_vel, which it
// holds for 0.5 s, as diff_drive_controller's timeout does).
class RosDrivers {
 public:
  explicit RosDrivers(CyclonePeer& peer)
      : peer_(peer),
        info_(peer.Writer("/camera/depth/camera_info", sensor_msgs_msg_CameraInfo_desc)),
        depth_(peer.Writer("/camera/depth/image_rect_raw", sensor_msgs_msg_Image_desc)),
        odom_(peer.Writer("/odom", nav_msgs_msg_Odometry_desc)),
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
  ~RosDrivers() {
    stop_ = true;
    thread_.join();
  }
  // The fastest forward command the base got, and the distance it drove.
  double fastest_command() const { return fastest_command_.load(); }
  double driven() const { return x_.load(); }
  // Sends one depth image in an encoding corridor must refuse.
  void SendBadImage() {
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

 private:
  static constexpr int kWidth = 160;
  static constexpr int kHeight = 120;
  static constexpr double kF = 90.0;
  static constexpr double kCx = 79.5;
  static constexpr double kCy = 59.5;

  void Run() {
    using Clock = std::chrono::steady_clock;
    auto next_frame = Clock::now();
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
        next_frame = now + 100ms;
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
      std::this_thread::sleep_for(20ms);
    }
  }
  static builtin_interfaces_msg_Time Stamp() {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
    return {static_cast<std::int32_t>(ns / 1000000000), static_cast<std::uint32_t>(ns % 1000000000)};
  }

  CyclonePeer& peer_;
  dds_entity_t info_;
  dds_entity_t depth_;
  dds_entity_t odom_;
  dds_entity_t cmd_vel_;
  std::vector<std::uint16_t> floor_;
  std::atomic<bool> stop_{false};
  std::atomic<double> fastest_command_{0.0};
  std::atomic<double> x_{0.0};
  std::thread thread_;
};

TEST(DdsInterop, CorridorRunsOnRos2DriversAndAToolDrivesItThroughThem) {
  const int domain = Domain(2);
  CyclonePeer peer(domain);
  RosDrivers drivers(peer);  // before corridord: it waits for the camera's info
  const std::string devices =
      "  cmd_vel_topic: /corridor/cmd_vel\n"
      "  devices:\n"
      "    camera: {depth_topic: /camera/depth/image_rect_raw, info_topic: /camera/depth/camera_info, "
      "mount_x_m: 0.1, mount_height_m: 0.3, tilt_deg: 10}\n"
      "    base: {odom_topic: /odom, cmd_vel_topic: /cmd_vel, max_linear_mps: 0.5}\n";
  Daemon daemon(domain, /*allow_writes=*/true, devices);
  EXPECT_NE(daemon.log().find("dds: camera 160 x 120"), std::string::npos) << daemon.log();
  drivers.SendBadImage();

  // A ROS 2 tool's teleop, on the topic corridor takes it on: through the command gate to the base's /cmd_vel.
  const dds_entity_t teleop = peer.Writer("/corridor/cmd_vel", geometry_msgs_msg_Twist_desc);
  const dds_entity_t state = peer.Reader("/corridor/state", std_msgs_msg_String_desc);
  StateWatch watch;
  ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch), [&] { return peer.Matched(teleop) > 0 && watch.latest.contains("pose"); }, 20s))
      << daemon.log();
  for (int i = 0; i < 20; ++i) {
    SendTwist(teleop, 0.25, 0.0);
    peer.Take<std_msgs_msg_String>(state, std::ref(watch));
    std::this_thread::sleep_for(100ms);
  }
  SendTwist(teleop, 0.0, 0.0);
  EXPECT_NEAR(drivers.fastest_command(), 0.25, 0.03) << daemon.log();
  EXPECT_GT(drivers.driven(), 0.25);
  // corridor follows the base's odometry: its pose (odometry localization from sim.start) moved with it.
  peer.TakeUntil<std_msgs_msg_String>(state, std::ref(watch), [] { return false; }, 500ms);
  ASSERT_TRUE(watch.latest["pose"].is_object()) << watch.latest.dump();
  EXPECT_GT(std::hypot(watch.latest["pose"]["x"].get<double>() - 24.38, watch.latest["pose"]["y"].get<double>() - 24.07),
            0.2)
      << watch.latest.dump();
  EXPECT_NE(daemon.log().find("dds camera: a sample was dropped"), std::string::npos) << daemon.log();
}

}  // namespace
}  // namespace corridor::testing
