// One localization update (issue 20: <= 5 ms at the 99th percentile) on one core, away from the daemon's other
// threads: Monte Carlo localization in the Willow Garage map (the daemon's options) following the robot down the
// start corridor and round its corner, from the simulator's laser (360 beams) or its depth camera's scan (320 x 240),
// with the simulator's wheel-odometry noise. Each benchmark iteration is one scan; the counters give the update's
// percentiles over the run's scans, the particle count and the error to the true path. Results: docs/benchmarks.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "drivers/sim/sensors.h"
#include "nav/ground/depth_scan.h"
#include "nav/localization/monte_carlo.h"
#include "nav/localization/range_scan.h"

namespace corridor {
namespace {

const drivers::sim::World& Willow() {
  static const drivers::sim::World world =
      drivers::sim::LoadWorld(std::string(CORRIDOR_SOURCE_DIR) + "/config/worlds/willow_garage/willow-full-0.05.yaml",
                              drivers::sim::WorldOptions{});
  return world;
}

struct Step {
  nav::Pose2 truth;
  nav::Pose2 odom;  // noisy wheel odometry
  nav::RangeScan scan;
};

// The true path: north up the start corridor 8.4 m, a quarter turn on the spot, 4.2 m west; a scan every 0.06 m or
// 3.4 degrees (past the filter's update thresholds, 0.05 m and 3 degrees: every scan is a full update).
std::vector<nav::Pose2> Path() {
  std::vector<nav::Pose2> path;
  nav::Pose2 p{24.38, 24.07, 1.5708};
  for (int i = 0; i < 140; ++i, p = p * nav::Pose2{0.06, 0.0, 0.0}) path.push_back(p);
  for (int i = 0; i < 26; ++i, p = p * nav::Pose2{0.0, 0.0, 1.5708 / 26}) path.push_back(p);
  for (int i = 0; i < 70; ++i, p = p * nav::Pose2{0.06, 0.0, 0.0}) path.push_back(p);
  return path;
}

// The simulator's odometry noise (drivers/sim/diff_drive_sim.h: 1 % of distance, 2 % of rotation) applied per step.
std::vector<nav::Pose2> NoisyOdometry(const std::vector<nav::Pose2>& path) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<nav::Pose2> odom{path.front()};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const nav::Pose2 step = path[i - 1].Inverse() * path[i];
    const double d = step.translation().norm();
    const double t = 1.0 + 0.01 * normal(rng);
    odom.push_back(odom.back() * nav::Pose2{step.x_m * t, step.y_m * t,
                                            step.yaw_rad * (1.0 + 0.02 * normal(rng)) + 0.002 * d * normal(rng)});
  }
  return odom;
}

const std::vector<Step>& LaserSteps() {
  static const std::vector<Step> steps = [] {
    const drivers::sim::RayCaster caster(Willow().mesh);
    const drivers::sim::SimLaserOptions options;
    const nav::Pose2 base_T_laser;
    const std::vector<nav::Pose2> path = Path();
    const std::vector<nav::Pose2> odom = NoisyOdometry(path);
    std::mt19937 rng(1);
    std::vector<Step> out;
    for (std::size_t i = 0; i < path.size(); ++i) {
      Eigen::Isometry3d world_T_laser = path[i].ToIsometry3();
      world_T_laser.translation().z() = options.mount_height_m;
      drivers::LaserScan scan;
      drivers::sim::CastScan(caster, world_T_laser, options, rng, scan);
      nav::RangeLimits limits;
      limits.max_range_m = scan.range_max_m;
      out.push_back(
          {path[i], odom[i],
           nav::ScanFromRanges(base_T_laser, scan.angle_min_rad, scan.angle_increment_rad, scan.ranges, limits)});
    }
    return out;
  }();
  return steps;
}

const std::vector<Step>& DepthSteps() {
  static const std::vector<Step> steps = [] {
    const drivers::sim::RayCaster caster(Willow().mesh);
    const drivers::sim::SimCameraOptions options;
    const drivers::sim::RgbdRenderer renderer(caster, options);
    const nav::PinholeCamera camera = drivers::sim::MakeCameraInfo(options).camera;
    nav::DepthScanOptions scan_options;  // the daemon's (server/config/config.h)
    scan_options.segment_gap_m = 0.0;
    scan_options.average_within_m = 0.15;
    scan_options.max_range_m = 4.0;
    nav::DepthScan depth_scan(camera, scan_options);
    const std::vector<nav::Pose2> path = Path();
    const std::vector<nav::Pose2> odom = NoisyOdometry(path);
    std::mt19937 rng(1);
    std::vector<Step> out;
    for (std::size_t i = 0; i < path.size(); ++i) {
      drivers::RgbdFrame frame;
      renderer.Render(path[i].ToIsometry3() * camera.base_T_camera, rng, frame);
      nav::RangeScan range;
      for (const Eigen::Vector2d& p : depth_scan.Process(frame.depth_mm)) range.hits.push_back(p.cast<float>());
      for (const Eigen::Vector2d& p : depth_scan.misses()) range.misses.push_back(p.cast<float>());
      out.push_back({path[i], odom[i], std::move(range)});
    }
    return out;
  }();
  return steps;
}

nav::MonteCarloOptions DaemonOptions(bool depth) {
  nav::MonteCarloOptions o;  // config/corridor.yaml's localization.mcl
  o.update_angle_rad = 3.0 * 3.14159265 / 180.0;
  if (depth) {
    o.max_range_m = 4.0;
    o.doubtful_after = 30;
  }
  return o;
}

void Run(benchmark::State& state, const std::vector<Step>& steps, bool depth) {
  const nav::OccupancyGrid& map = *Willow().source_map;
  const auto start_filter = [&] {
    auto mcl = std::make_unique<nav::MonteCarloLocalization>(map, DaemonOptions(depth), 1);
    mcl->SetPose(steps.front().truth, 0.1, 0.087);
    return mcl;
  };
  std::unique_ptr<nav::MonteCarloLocalization> mcl = start_filter();
  std::vector<double> ms;
  double particles = 0.0;
  double squared_error = 0.0;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const nav::LocalizationEstimate& e = mcl->Update(steps[i].odom, steps[i].scan);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    particles += e.particles;
    squared_error += (e.pose.translation() - steps[i].truth.translation()).squaredNorm();
    if (++i == steps.size()) {
      i = 0;  // round again from the start: a new filter there
      state.PauseTiming();
      mcl = start_filter();
      state.ResumeTiming();
    }
  }
  std::sort(ms.begin(), ms.end());
  state.counters["p50_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
  state.counters["particles"] = particles / static_cast<double>(ms.size());
  state.counters["rmse_cm"] = 100.0 * std::sqrt(squared_error / static_cast<double>(ms.size()));
}

void BM_UpdateLaser(benchmark::State& state) { Run(state, LaserSteps(), false); }
BENCHMARK(BM_UpdateLaser)->Unit(benchmark::kMillisecond)->Iterations(708);

void BM_UpdateDepth(benchmark::State& state) { Run(state, DepthSteps(), true); }
BENCHMARK(BM_UpdateDepth)->Unit(benchmark::kMillisecond)->Iterations(708);

}  // namespace
}  // namespace corridor

BENCHMARK_MAIN();
