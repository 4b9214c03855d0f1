// corridord as ROS 2 tools see it, checked with a second DDS vendor: a Cyclone DDS peer (tests/dds/cyclone_peer.h)
// on loopback receives /odom, /tf, /map and corridor's state from the real daemon running the simulator, drives the
// robot with /cmd_vel and sees it move, sends RViz's /goal_pose and sees the mission succeed; and, with writes off,
// sees /cmd_vel refused.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <set>
#include <string>

#include "tests/dds/cyclone_peer.h"
#include "tests/dds/idl/geometry_msgs.h"
#include "tests/dds/idl/nav_msgs.h"
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

// The tree's configuration with DDS on loopback (unicast peers: loopback has no multicast) in `domain`.
std::string DdsConfig(int domain, bool allow_writes) {
  const fs::path source = CORRIDOR_SOURCE_DIR;
  std::string config = ReadFile(source / "config/corridor.yaml");
  const std::size_t begin = config.find("\ndds:\n");
  const std::size_t end = config.find("\nlog:\n");
  if (begin == std::string::npos || end == std::string::npos) return "";
  std::string dds = "\ndds:\n  enabled: true\n  peers: [127.0.0.1]\n  interfaces: [lo]\n";
  dds += "  domain_id: " + std::to_string(domain) + "\n";
  dds += allow_writes ? "  allow_writes: true\n" : "  allow_writes: false\n";
  config.replace(begin, end - begin, dds);
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
  Daemon(int domain, bool allow_writes) {
    dir_ = fs::temp_directory_path() / ("corridor-dds-" + std::to_string(::getpid()) + "-" + std::to_string(domain));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string config = DdsConfig(domain, allow_writes);
    EXPECT_FALSE(config.empty()) << "config/corridor.yaml has no dds: section before log:";
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

}  // namespace
}  // namespace corridor::testing
