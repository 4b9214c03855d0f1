// Docking accuracy and time: the daemon's graph in lockstep with the simulator, in a 4 x 3 m room with a dock, the
// robot starting at random poses with the simulator's odometry noise (1 % of distance, 2 % of rotation) and its pose
// from wheel odometry (so the map's idea of the dock drifts as it drives). Each run POSTs /api/v1/dock through the
// graph's API and steps until the mission ends; the error is the simulator's truth against the dock's docked pose.
// Not a Google Benchmark: the result is a distribution of errors (docs/benchmarks.md, Docking).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "drivers/sim/sim_robot.h"
#include "server/app/graph.h"
#include "server/runtime/topics.h"
#include "server/store/store.h"

namespace {

using namespace corridor;
namespace fs = std::filesystem;

struct Run {
  bool docked = false;
  std::string error;
  double position_m = 0.0;
  double yaw_deg = 0.0;
  double time_s = 0.0;
};

// POSTs `path` through the graph's API, as a building system would; the HTTP status.
int Post(server::Graph& graph, const char* path) {
  server::Request request{server::http::verb::post, path, 11};
  request.set(server::http::field::content_type, "application/json");
  request.body() = "{}";
  request.prepare_payload();
  std::optional<int> status;
  graph.api().Handle(request, [&status](server::Response response) { status = response.result_int(); });
  while (!status && graph.executors().RunUntilIdle() > 0) {
  }
  return status.value_or(0);
}

Run DockOnce(std::uint32_t seed, const fs::path& state_dir) {
  const nav::Pose2 dock{3.2, 1.5, 0.0};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0.6, 2.0), y(0.6, 2.4), yaw(-std::numbers::pi, std::numbers::pi);
  drivers::sim::SimOptions sim;
  sim.start = {x(rng), y(rng), yaw(rng)};
  sim.seed = seed;
  sim.laser.enabled = false;
  sim.dock = drivers::sim::SimDockOptions{};
  sim.dock->pose = dock;
  drivers::sim::World world = drivers::sim::WorldFromMap(drivers::sim::RoomMap(4.0, 3.0, 0.05), {});
  drivers::sim::AddDock(world, drivers::sim::SimDock(*sim.dock));
  const nav::OccupancyGrid map = *world.source_map;
  drivers::sim::SimRobot robot(std::make_shared<const drivers::sim::World>(std::move(world)), sim);

  server::Config config;
  config.store.state_dir = state_dir;
  config.sim.robot = sim;
  config.devices.laser.driver = server::DeviceDriver::kNone;
  config.localization.source = server::LocalizationOptions::Source::kOdometry;
  server::ApplyDerivedOptions(config);
  const server::Devices devices{&robot, robot, nullptr, &robot, &robot, nullptr};
  server::Graph graph(config, devices, server::NamedMap{"room", map}, server::Schedule::kLockstep);
  graph.store().PutPlace("room", nav::Place{"dock", "dock", dock, nav::PlaceKind::kDock});
  graph.Start();
  Run run;
  const int status = Post(graph, "/api/v1/dock");
  if (status != 201) {
    run.error = "POST /api/v1/dock: " + std::to_string(status);
    return run;
  }
  const double start_s = drivers::ToSeconds(robot.now_ns());
  while (drivers::ToSeconds(robot.now_ns()) - start_s < 180.0) {
    graph.Step();
    const auto mission = graph.bus().Get(server::topics::kMission).latest();
    if (!mission || mission->status == nav::MissionStatus::kActive) continue;
    run.docked = mission->status == nav::MissionStatus::kSucceeded;
    run.error = mission->error;
    break;
  }
  const nav::Pose2 error = dock.Inverse() * robot.true_pose();
  run.position_m = error.translation().norm();
  run.yaw_deg = std::abs(error.yaw_rad) * 180.0 / std::numbers::pi;
  run.time_s = drivers::ToSeconds(robot.now_ns()) - start_s;
  graph.Stop();
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::atoi(argv[1]) : 20;
  if (runs < 1) {
    std::fprintf(stderr, "usage: docking_bench [RUNS]   (default 20)\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);
  std::string pattern = (fs::temp_directory_path() / "corridor-docking-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) return 1;
  std::vector<Run> results;
  for (int i = 0; i < runs; ++i) {
    const fs::path dir = fs::path(pattern) / std::to_string(i);
    fs::create_directories(dir);
    results.push_back(DockOnce(static_cast<std::uint32_t>(i + 1), dir));
    const Run& r = results.back();
    std::printf("run %2d: %s  %5.1f mm  %4.2f deg  %5.1f s  %s\n", i + 1, r.docked ? "docked" : "FAILED",
                r.position_m * 1000.0, r.yaw_deg, r.time_s, r.error.c_str());
  }
  fs::remove_all(pattern);
  std::vector<double> position, yaw, time;
  int docked = 0;
  for (const Run& r : results) {
    if (!r.docked) continue;
    ++docked;
    position.push_back(r.position_m * 1000.0);
    yaw.push_back(r.yaw_deg);
    time.push_back(r.time_s);
  }
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  const auto max = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  std::printf(
      "docked %d of %d; position error mean %.1f mm, max %.1f mm; heading error mean %.2f deg, max %.2f deg; "
      "time from the request mean %.1f s\n",
      docked, runs, mean(position), max(position), mean(yaw), max(yaw), mean(time));
  return docked == runs ? 0 : 1;
}
