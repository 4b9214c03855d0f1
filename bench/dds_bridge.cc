// What ROS 2 over DDS costs the robot, measured on the real corridord with a Cyclone DDS peer on loopback (the same
// fixtures as tests/dds_interop_test.cc). Not a Google Benchmark: two daemons and one DDS round trip loop.
//   1. The bridge's CPU: corridord driving a mission round the Willow Garage start three times, once with DDS off
//      (the baseline) and once with DDS on and the peer subscribed to every topic published by default; the
//      difference in the process's CPU time is the bridge's. The control loop's depth-frame-to-command p99 (from
//      /api/v1/state) in both.
//   2. /cmd_vel to the base: corridord on ROS 2 drivers played by the peer (the simulator off); the peer sends a
//      Twist on corridor's teleop topic and times the base command corridor sends on /cmd_vel in answer. The round
//      trip holds two DDS hops on top of corridor's own time from receipt to command, so it bounds it from above.
//   build/bench/dds_bridge [seconds=30]
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "server/api/http_client.h"
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
using Clock = std::chrono::steady_clock;

// The API over HTTP with the daemon's admin token, through corridor's own HTTP client (as a building system calls it).
nlohmann::json Api(const DaemonProcess& daemon, boost::beast::http::verb method, const std::string& path,
                   const std::string& body = "") {
  boost::asio::io_context io;
  boost::asio::ssl::context tls(boost::asio::ssl::context::tls_client);
  boost::beast::http::request<boost::beast::http::string_body> request{method, path, 11};
  request.set(boost::beast::http::field::authorization, "Bearer " + daemon.token());
  request.set(boost::beast::http::field::content_type, "application/json");
  request.body() = body;
  request.prepare_payload();
  server::HttpAnswer answer;
  server::HttpExchange(
      io, tls, server::ParseHttpUrl("http://127.0.0.1:" + std::to_string(daemon.port())), request, 10.0,
      [&answer](server::HttpAnswer a) { answer = std::move(a); }, 1 << 20);
  io.run();
  if (answer.status == 0) throw std::runtime_error(path + ": " + answer.error);
  return nlohmann::json::parse(answer.body, nullptr, false);
}

// The process's CPU time so far (user + system), in seconds.
double CpuSeconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  double ticks = 0.0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14 || i == 15) ticks += std::stod(field);
  }
  return ticks / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

struct MissionRun {
  double cpu_percent = 0.0;
  double control_p99_ms = 0.0;
  std::map<std::string, int> received;  // by topic, over the window
};

// A mission round the start, measured over `seconds`; with `domain` >= 0, DDS on and the peer subscribed
// to everything the bridge publishes by default; with `keystore`, both secured by enclaves of it.
MissionRun Mission(int domain, double seconds, Keystore* keystore = nullptr) {
  const std::string security =
      keystore != nullptr ? "  security: {enclave: " + keystore->Enclave("corridor") + "}\n" : "";
  DaemonProcess daemon(CORRIDORD, CORRIDOR_SOURCE_DIR, domain, false, security);
  MissionRun run;
  std::unique_ptr<CyclonePeer> peer;
  std::vector<std::pair<std::string, dds_entity_t>> readers;
  if (domain >= 0) {
    peer = std::make_unique<CyclonePeer>(domain, keystore != nullptr ? keystore->Enclave("tool") : "");
    readers = {
        {"/odom", peer->Reader("/odom", nav_msgs_msg_Odometry_desc)},
        {"/tf", peer->Reader("/tf", tf2_msgs_msg_TFMessage_desc, PeerQos::kTf)},
        {"/tf_static", peer->Reader("/tf_static", tf2_msgs_msg_TFMessage_desc, PeerQos::kLatched)},
        {"/scan", peer->Reader("/scan", sensor_msgs_msg_LaserScan_desc)},
        {"/map", peer->Reader("/map", nav_msgs_msg_OccupancyGrid_desc, PeerQos::kLatched)},
        {"/plan", peer->Reader("/plan", nav_msgs_msg_Path_desc)},
        {"/amcl_pose", peer->Reader("/amcl_pose", geometry_msgs_msg_PoseWithCovarianceStamped_desc, PeerQos::kLatched)},
        {"/diagnostics", peer->Reader("/diagnostics", diagnostic_msgs_msg_DiagnosticArray_desc)},
        {"/corridor/state", peer->Reader("/corridor/state", std_msgs_msg_String_desc)}};
  }
  const auto drain = [&](bool count) {
    for (const auto& [topic, reader] : readers) {
      for (;;) {
        void* samples[1] = {nullptr};
        dds_sample_info_t info[1];
        const dds_return_t n = dds_take(reader, samples, info, 1, 1);
        if (n <= 0) break;
        if (count && info[0].valid_data) ++run.received[topic];
        dds_return_loan(reader, samples, n);
      }
    }
  };
  const auto settle = Clock::now() + 3s;
  while (Clock::now() < settle) {
    drain(false);
    std::this_thread::sleep_for(20ms);
  }
  // The localization test's round near the start, three times over.
  nlohmann::json waypoints = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (const auto& [x, y] : {std::pair{24.4, 26.5}, {25.0, 27.2}, {24.4, 24.6}})
      waypoints.push_back({{"x", x}, {"y", y}});
  }
  const nlohmann::json started =
      Api(daemon, boost::beast::http::verb::post, "/api/v1/missions", nlohmann::json{{"waypoints", waypoints}}.dump());
  if (!started.is_object() || !started.contains("id")) throw std::runtime_error("no mission: " + started.dump());
  const double cpu0 = CpuSeconds(daemon.pid());
  const auto t0 = Clock::now();
  while (Clock::now() - t0 < std::chrono::duration<double>(seconds)) {
    drain(true);
    std::this_thread::sleep_for(20ms);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  run.cpu_percent = 100.0 * (CpuSeconds(daemon.pid()) - cpu0) / wall;
  const nlohmann::json state = Api(daemon, boost::beast::http::verb::get, "/api/v1/state");
  run.control_p99_ms = state["control_latency"].value("p99_ms", -1.0);
  return run;
}

struct Percentiles {
  double p50 = 0.0, p99 = 0.0, max = 0.0;
};
Percentiles Of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return {};
  return {v[v.size() / 2], v[std::min(v.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(v.size())))],
          v.back()};
}

// /corridor/cmd_vel from a ROS 2 tool to the base's /cmd_vel, `samples` times at 20 Hz.
std::vector<double> CmdVelRoundTrips(int domain, int samples, int& missed) {
  CyclonePeer peer(domain);
  RosDrivers drivers(peer);
  const std::string devices =
      "  cmd_vel_topic: /corridor/cmd_vel\n"
      "  devices:\n"
      "    camera: {mount_x_m: 0.1, mount_height_m: 0.3, tilt_deg: 10}\n"
      "    base: {max_linear_mps: 0.5, max_angular_rps: 1.5}\n";
  DaemonProcess daemon(CORRIDORD, CORRIDOR_SOURCE_DIR, domain, true, devices);
  const dds_entity_t teleop = peer.Writer("/corridor/cmd_vel", geometry_msgs_msg_Twist_desc);
  const dds_entity_t base = peer.Reader("/cmd_vel", geometry_msgs_msg_Twist_desc);
  const auto matched = Clock::now() + 10s;
  while (peer.Matched(teleop) == 0 && Clock::now() < matched) std::this_thread::sleep_for(10ms);
  std::this_thread::sleep_for(1s);
  std::vector<double> ms;
  missed = 0;
  for (int i = 0; i < samples; ++i) {
    peer.Take<geometry_msgs_msg_Twist>(base, [](const auto&) {});
    // A turn rate of its own marks this request's answer among the control loop's periodic commands.
    const double marker = 0.01 + 0.0001 * (i % 1000);
    const auto sent = Clock::now();
    SendTwist(teleop, 0.0, marker);
    bool answered = false;
    while (!answered && Clock::now() - sent < 200ms) {
      peer.Take<geometry_msgs_msg_Twist>(base, [&](const geometry_msgs_msg_Twist& t) {
        if (!answered && std::abs(t.angular.z - marker) < 1e-9) {
          ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - sent).count());
          answered = true;
        }
      });
      if (!answered) std::this_thread::sleep_for(50us);
    }
    if (!answered) ++missed;
    std::this_thread::sleep_until(sent + 50ms);
  }
  SendTwist(teleop, 0.0, 0.0);
  return ms;
}

int Main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 30.0;
  const MissionRun off = Mission(-1, seconds);
  const MissionRun on = Mission(Domain(0), seconds);
  Keystore keystore(CORRIDOR_SOURCE_DIR, "corridor-dds-bench");
  const MissionRun secured = Mission(Domain(2), seconds, &keystore);
  std::printf(
      "corridord CPU driving a mission, %.0f s: DDS off %.1f %% of a core, on with a peer subscribed to "
      "everything %.1f %%: the bridge %.1f %%; with DDS Security %.1f %%: the bridge %.1f %%\n",
      seconds, off.cpu_percent, on.cpu_percent, on.cpu_percent - off.cpu_percent, secured.cpu_percent,
      secured.cpu_percent - off.cpu_percent);
  std::printf("control loop, depth frame to command p99: DDS off %.2f ms, on %.2f ms, secured %.2f ms\n",
              off.control_p99_ms, on.control_p99_ms, secured.control_p99_ms);
  std::printf("samples the peer took in the window:");
  for (const auto& [topic, n] : on.received) std::printf(" %s %d;", topic.c_str(), n);
  std::printf("\nsecured:");
  for (const auto& [topic, n] : secured.received) std::printf(" %s %d;", topic.c_str(), n);
  std::printf("\n");
  int missed = 0;
  const Percentiles rt = Of(CmdVelRoundTrips(Domain(1), 400, missed));
  std::printf(
      "/corridor/cmd_vel -> corridor -> base /cmd_vel round trip: p50 %.2f ms, p99 %.2f ms, max %.2f ms "
      "(%d of 400 unanswered within 200 ms)\n",
      rt.p50, rt.p99, rt.max, missed);
  return 0;
}

}  // namespace
}  // namespace corridor::testing

int main(int argc, char** argv) {
  try {
    return corridor::testing::Main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "dds_bridge: " << e.what() << "\n";
    return 1;
  }
}
