// corridord as ROS 2 tools and drivers see it, checked with a second DDS vendor: a Cyclone DDS peer
// (tests/dds/cyclone_peer.h) on loopback receives /odom, /tf, /map and corridor's state from the real daemon running
// the simulator, drives the robot with /cmd_vel and sees it move, sends RViz's /goal_pose and sees the mission
// succeed; with writes off, sees /cmd_vel refused; and, with the simulator off, plays the robot's ROS 2 drivers (a
// depth camera and a base) that corridord runs on; with DDS Security, lets in only peers of its keystore.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "tests/dds/cyclone_peer.h"
#include "tests/dds/idl/diagnostic_msgs.h"
#include "tests/dds/idl/geometry_msgs.h"
#include "tests/dds/idl/nav_msgs.h"
#include "tests/dds/idl/sensor_msgs.h"
#include "tests/dds/idl/std_msgs.h"
#include "tests/dds/idl/tf2_msgs.h"
#include "tests/dds/ros2_fixtures.h"

namespace corridor::testing {
namespace {

using namespace std::chrono_literals;

// corridord from this build, with DDS on loopback in `domain`.
class Daemon : public DaemonProcess {
 public:
  Daemon(int domain, bool allow_writes, const std::string& extra = "", const std::string& devices = "")
      : DaemonProcess(CORRIDORD, CORRIDOR_SOURCE_DIR, domain, allow_writes, extra, devices) {}
  ~Daemon() { EXPECT_TRUE(Stop()) << "corridord did not exit cleanly:\n" << log(); }
};

// Sends `speed` forward on `cmd_vel` at 10 Hz, as teleop_twist_keyboard does, for `ticks` ticks, then a stop;
// returns the fastest speed odometry reported meanwhile.
double FastestWhileDriving(CyclonePeer& peer, dds_entity_t cmd_vel, dds_entity_t odom, double speed, int ticks) {
  double fastest = 0.0;
  for (int i = 0; i < ticks; ++i) {
    SendTwist(cmd_vel, speed, 0.0);
    peer.Take<nav_msgs_msg_Odometry>(
        odom, [&](const nav_msgs_msg_Odometry& o) { fastest = std::max(fastest, std::abs(o.twist.twist.linear.x)); });
    std::this_thread::sleep_for(100ms);
  }
  SendTwist(cmd_vel, 0.0, 0.0);
  return fastest;
}

TEST(DdsInterop, RosToolSeesTheRobotDrivesItAndSendsAGoal) {
  const int domain = Domain(0);
  Daemon daemon(domain, /*allow_writes=*/true, "  camera_hz: 2\n");
  CyclonePeer peer(domain);
  const dds_entity_t map = peer.Reader("/map", nav_msgs_msg_OccupancyGrid_desc, PeerQos::kLatched);
  const dds_entity_t scan = peer.Reader("/scan", sensor_msgs_msg_LaserScan_desc);
  const dds_entity_t plan = peer.Reader("/plan", nav_msgs_msg_Path_desc);
  const dds_entity_t amcl_pose =
      peer.Reader("/amcl_pose", geometry_msgs_msg_PoseWithCovarianceStamped_desc, PeerQos::kLatched);
  const dds_entity_t diagnostics = peer.Reader("/diagnostics", diagnostic_msgs_msg_DiagnosticArray_desc);
  const dds_entity_t battery = peer.Reader("/battery_state", sensor_msgs_msg_BatteryState_desc);
  const dds_entity_t depth = peer.Reader("/camera/depth/image_raw", sensor_msgs_msg_Image_desc);
  const dds_entity_t camera_info = peer.Reader("/camera/depth/camera_info", sensor_msgs_msg_CameraInfo_desc);
  const dds_entity_t initial_pose = peer.Writer("/initialpose", geometry_msgs_msg_PoseWithCovarianceStamped_desc);
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

  // The laser, localization's estimate, the nodes' health, and the depth camera at the rate asked for.
  std::string scan_frame;
  std::size_t beams = 0;
  ASSERT_TRUE(peer.TakeUntil<sensor_msgs_msg_LaserScan>(
      scan,
      [&](const sensor_msgs_msg_LaserScan& m) {
        scan_frame = m.header.frame_id;
        beams = m.ranges._length;
      },
      [&] { return beams > 0; }, 5s));
  EXPECT_EQ(scan_frame, "laser");
  double covariance_xx = -1.0;
  ASSERT_TRUE(peer.TakeUntil<geometry_msgs_msg_PoseWithCovarianceStamped>(
      amcl_pose, [&](const auto& m) { covariance_xx = m.pose.covariance[0]; }, [&] { return covariance_xx >= 0.0; },
      5s));
  std::set<std::string> healthy;
  ASSERT_TRUE(peer.TakeUntil<diagnostic_msgs_msg_DiagnosticArray>(
      diagnostics,
      [&](const diagnostic_msgs_msg_DiagnosticArray& m) {
        for (std::uint32_t i = 0; i < m.status._length; ++i) {
          if (m.status._buffer[i].level == 0) healthy.insert(m.status._buffer[i].name);
        }
      },
      [&] {
        return healthy.contains("corridor/control") && healthy.contains("corridor/dds") &&
               healthy.contains("corridor/devices/camera") && healthy.contains("corridor/devices/base");
      },
      5s));
  // The simulator's battery, as ROS 2's BatteryState says one (about once a second).
  float percentage = -1.0f;
  std::uint8_t supply_status = 0;
  ASSERT_TRUE(peer.TakeUntil<sensor_msgs_msg_BatteryState>(
      battery,
      [&](const sensor_msgs_msg_BatteryState& m) {
        percentage = m.percentage;
        supply_status = m.power_supply_status;
      },
      [&] { return percentage >= 0.0f; }, 5s));
  EXPECT_GT(percentage, 0.0f);
  EXPECT_LE(percentage, 1.0f);
  EXPECT_TRUE(supply_status == 1 || supply_status == 2 || supply_status == 4) << int{supply_status};
  std::string encoding;
  std::uint32_t image_bytes = 0;
  double fx = 0.0;
  ASSERT_TRUE(peer.TakeUntil<sensor_msgs_msg_Image>(
      depth,
      [&](const sensor_msgs_msg_Image& m) {
        encoding = m.encoding;
        image_bytes = m.data._length;
        EXPECT_EQ(m.step * m.height, m.data._length);
      },
      [&] { return image_bytes > 0; }, 5s));
  EXPECT_EQ(encoding, "16UC1");
  ASSERT_TRUE(peer.TakeUntil<sensor_msgs_msg_CameraInfo>(
      camera_info, [&](const auto& m) { fx = m.k[0]; }, [&] { return fx > 0.0; }, 5s));

  // RViz's 2D Pose Estimate where the robot stands: localization takes it (the API answers 202).
  nav_msgs_msg_Odometry here{};
  peer.TakeUntil<nav_msgs_msg_Odometry>(
      odom, [&](const nav_msgs_msg_Odometry& o) { here = o; }, [] { return false; }, 200ms);
  {
    StateWatch now;
    ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
        state, std::ref(now), [&] { return now.latest.contains("pose") && now.latest["pose"].is_object(); }, 5s));
    geometry_msgs_msg_PoseWithCovarianceStamped estimate{};
    estimate.header.frame_id = const_cast<char*>("map");
    estimate.pose.pose.position.x = now.latest["pose"]["x"].get<double>();
    estimate.pose.pose.position.y = now.latest["pose"]["y"].get<double>();
    const double yaw = now.latest["pose"]["yaw"].get<double>();
    estimate.pose.pose.orientation.z = std::sin(yaw / 2);
    estimate.pose.pose.orientation.w = std::cos(yaw / 2);
    estimate.pose.covariance[0] = estimate.pose.covariance[7] = 0.25 * 0.25;  // RViz's default spread
    estimate.pose.covariance[35] = 0.07;
    ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
        state, std::ref(now), [&] { return peer.Matched(initial_pose) > 0; }, 5s));
    ASSERT_EQ(dds_write(initial_pose, &estimate), DDS_RETCODE_OK);
    peer.TakeUntil<std_msgs_msg_String>(
        state, std::ref(now), [&] { return daemon.log().find("dds: /initialpose taken") != std::string::npos; }, 5s);
    EXPECT_NE(daemon.log().find("dds: /initialpose taken"), std::string::npos) << daemon.log();
  }

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

  // RViz's 2D Goal Pose: back where the robot started (sim.start), facing the way it came; the mission must succeed.
  StateWatch watch;
  const double gx = 24.38;
  const double gy = 24.07;
  geometry_msgs_msg_PoseStamped goal{};
  goal.header.frame_id = const_cast<char*>("map");
  goal.pose.position.x = gx;
  goal.pose.position.y = gy;
  goal.pose.orientation.z = std::sin(-M_PI / 4);
  goal.pose.orientation.w = std::cos(-M_PI / 4);
  ASSERT_TRUE(peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch), [&] { return peer.Matched(goal_pose) > 0; }, 10s));
  // A goal the console would refuse (off the map) is refused on arrival the same way: logged, and nothing starts.
  {
    auto off_map = goal;
    off_map.pose.position.x = 1000.0;
    ASSERT_EQ(dds_write(goal_pose, &off_map), DDS_RETCODE_OK);
    const auto refused = [&] {
      return daemon.log().find("dds: /goal_pose refused (goal_outside_map)") != std::string::npos;
    };
    peer.TakeUntil<std_msgs_msg_String>(state, std::ref(watch), refused, 10s);
    EXPECT_TRUE(refused()) << daemon.log();
    EXPECT_FALSE(watch.latest["mission"].is_object() && watch.latest["mission"].value("status", "") == "active")
        << watch.latest.dump();
  }
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
  // The mission's path went out on /plan, in the map frame, ending at the goal.
  std::size_t poses = 0;
  double end_x = 0.0, end_y = 0.0;
  peer.Take<nav_msgs_msg_Path>(plan, [&](const nav_msgs_msg_Path& p) {
    if (p.poses._length == 0) return;
    poses = p.poses._length;
    EXPECT_STREQ(p.header.frame_id, "map");
    end_x = p.poses._buffer[p.poses._length - 1].pose.position.x;
    end_y = p.poses._buffer[p.poses._length - 1].pose.position.y;
  });
  EXPECT_GT(poses, 1u);
  EXPECT_NEAR(end_x, gx, 0.1);
  EXPECT_NEAR(end_y, gy, 0.1);
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
  EXPECT_LT(FastestWhileDriving(peer, cmd_vel, odom, 0.3, 15), 0.01);
  EXPECT_NE(daemon.log().find("writes over DDS are off"), std::string::npos) << daemon.log();
}

TEST(DdsInterop, CorridorRunsOnRos2DriversAndAToolDrivesItThroughThem) {
  const int domain = Domain(2);
  CyclonePeer peer(domain);
  RosDrivers drivers(peer);  // before corridord: it waits for the camera's info
  const std::string devices =
      "  camera: {driver: dds, depth_topic: /camera/depth/image_rect_raw, info_topic: /camera/depth/camera_info, "
      "mount_x_m: 0.1, mount_height_m: 0.3, tilt_deg: 10}\n"
      "  laser: {driver: dds, topic: /scan, mount_height_m: 0.2}\n"
      "  base: {driver: dds, odom_topic: /odom, cmd_vel_topic: /cmd_vel, battery_topic: /battery_state, "
      "max_linear_mps: 0.5}\n";
  Daemon daemon(domain, /*allow_writes=*/true, "  cmd_vel_topic: /corridor/cmd_vel\n", devices);
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
  peer.TakeUntil<std_msgs_msg_String>(
      state, std::ref(watch), [] { return false; }, 500ms);
  ASSERT_TRUE(watch.latest["pose"].is_object()) << watch.latest.dump();
  EXPECT_GT(
      std::hypot(watch.latest["pose"]["x"].get<double>() - 24.38, watch.latest["pose"]["y"].get<double>() - 24.07), 0.2)
      << watch.latest.dump();
  EXPECT_NE(daemon.log().find("dds camera: a sample was dropped"), std::string::npos) << daemon.log();
  // The base driver's battery is the robot's: 42 % from its percentage of 0.42.
  ASSERT_TRUE(watch.latest["battery"].is_object()) << watch.latest.dump();
  EXPECT_NEAR(watch.latest["battery"]["percent"].get<double>(), 42.0, 0.5) << watch.latest["battery"].dump();
  EXPECT_FALSE(watch.latest["battery"]["charging"].get<bool>());
  // The driver's scans reach the tracker (its "scan" loop runs at the laser's rate).
  double scan_rate = 0.0;
  for (const auto& node : watch.latest["nodes"]) {
    if (node.value("name", "") != "tracking") continue;
    for (const auto& loop : node["callbacks"]) {
      if (loop.value("name", "") == "scan") scan_rate = loop.value("rate_hz", 0.0);
    }
  }
  EXPECT_NEAR(scan_rate, 20.0, 6.0) << watch.latest["nodes"].dump();
}

// With DDS Security (tools/dds-keystore's enclaves, Fast DDS's plugins in corridord, Cyclone's in the peer): a tool
// holding an enclave of the robot's keystore sees the robot and drives it; a peer without security, or with a
// certificate from another keystore's CA, is not let in: it sees nothing and its commands match no reader.
TEST(DdsInterop, SecuredDomainLetsInOnlyTheKeystoresPeers) {
  Keystore keystore(CORRIDOR_SOURCE_DIR, "corridor-dds-keystore");
  Keystore stranger(CORRIDOR_SOURCE_DIR, "corridor-dds-stranger");
  const std::string robot = keystore.Enclave("corridor");
  const std::string tool = keystore.Enclave("tool");
  const std::string impostor = stranger.Enclave("tool");
  const int domain = Domain(3);
  Daemon daemon(domain, /*allow_writes=*/true, "  security: {enclave: " + robot + "}\n");
  EXPECT_NE(daemon.log().find("secured by " + robot), std::string::npos) << daemon.log();

  {
    CyclonePeer trusted(domain, tool);
    const dds_entity_t odom = trusted.Reader("/odom", nav_msgs_msg_Odometry_desc);
    const dds_entity_t cmd_vel = trusted.Writer("/cmd_vel", geometry_msgs_msg_Twist_desc);
    ASSERT_TRUE(trusted.TakeUntil<nav_msgs_msg_Odometry>(
        odom, [](const auto&) {}, [&] { return trusted.Matched(cmd_vel) > 0; }, 30s))
        << daemon.log();
    EXPECT_NEAR(FastestWhileDriving(trusted, cmd_vel, odom, 0.3, 20), 0.3, 0.05) << daemon.log();
  }
  // One after the other (a process holds one Cyclone domain at a time), each given 5 s.
  for (const std::string& enclave : {std::string(), impostor}) {
    CyclonePeer peer(domain, enclave);
    const dds_entity_t odom = peer.Reader("/odom", nav_msgs_msg_Odometry_desc);
    const dds_entity_t cmd_vel = peer.Writer("/cmd_vel", geometry_msgs_msg_Twist_desc);
    int seen = 0;
    EXPECT_FALSE(peer.TakeUntil<nav_msgs_msg_Odometry>(
        odom, [&](const auto&) { ++seen; }, [&] { return seen > 0 || peer.Matched(cmd_vel) > 0; }, 5s))
        << (enclave.empty() ? "a peer without security" : "a peer of another keystore") << " was let in";
  }
  EXPECT_NE(daemon.log().find("failed authentication"), std::string::npos) << daemon.log();
}

}  // namespace
}  // namespace corridor::testing
