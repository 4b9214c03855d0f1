// The global planner across the Willow Garage building (1165 x 945 cells at 5 cm): the fast-marching costmap and
// the search, plain A* (f = g + h, distance_weight 0) beside DPoom's modified A* (f = g + h + d), in one run.
// Prints the comparison table of docs/benchmarks.md, then runs the timing benchmarks.
//   ./build/bench/planner_bench [--weight W] [--saturation S] [google benchmark flags]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "nav/map/map_io.h"
#include "nav/planner/planner.h"
#include "nav/tracking/traffic_map.h"

namespace corridor::nav {
namespace {

CostmapOptions g_modified;

const OccupancyGrid& Willow() {
  static const OccupancyGrid g =
      LoadMap(std::string(CORRIDOR_SOURCE_DIR) + "/config/worlds/willow_garage/willow-full-0.05.yaml");
  return g;
}

// Start and goal pairs across the building (map frame, metres), snapped to traversable cells by the caller.
const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& Queries() {
  static const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> q = {{{24.4, 24.1}, {50.0, 12.0}},
                                                                             {{8.0, 10.0}, {45.0, 38.0}},
                                                                             {{33.0, 40.0}, {15.0, 5.0}},
                                                                             {{12.0, 35.0}, {52.0, 30.0}},
                                                                             {{40.0, 8.0}, {10.0, 42.0}}};
  return q;
}

Eigen::Vector2d Snap(const Costmap& c, const Eigen::Vector2d& p) { return MostOpenCell(c, p, 3.0).value_or(p); }

double Ms(std::chrono::steady_clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

void PrintComparison() {
  using Clock = std::chrono::steady_clock;
  CostmapOptions plain_options = g_modified;
  plain_options.distance_weight = 0.0;
  auto t0 = Clock::now();
  const Costmap plain(Willow(), {}, plain_options);
  auto t1 = Clock::now();
  const Costmap modified(Willow(), {}, g_modified);
  auto t2 = Clock::now();
  std::printf("Willow Garage 1165 x 945 at 5 cm; robot radius %.2f m; d(n) weight %.1f, saturation %.2f m\n",
              g_modified.robot_radius_m, g_modified.distance_weight, g_modified.saturation_m);
  std::printf("costmap (obstacles, fast marching, costs): %.1f ms, %.1f ms\n\n", Ms(t1 - t0), Ms(t2 - t1));
  std::printf("%-5s %-9s %9s %9s %9s %10s %10s\n", "query", "planner", "plan ms", "expanded", "length m", "min clr m",
              "mean clr m");
  double ratio_sum = 0.0;
  for (std::size_t i = 0; i < Queries().size(); ++i) {
    const Eigen::Vector2d s = Snap(modified, Queries()[i].first);
    const Eigen::Vector2d g = Snap(modified, Queries()[i].second);
    double plain_length = 0.0;
    for (const auto& [name, costmap] : {std::pair{"plain", &plain}, std::pair{"modified", &modified}}) {
      const auto start = Clock::now();
      const PlanResult r = PlanPath(*costmap, s, g);
      const double ms = Ms(Clock::now() - start);
      if (!r.ok()) {
        std::printf("%-5zu %-9s failed: %s\n", i, name, r.detail.c_str());
        continue;
      }
      if (costmap == &plain)
        plain_length = r.plan.length_m;
      else
        ratio_sum += r.plan.length_m / plain_length;
      std::printf("%-5zu %-9s %9.1f %9d %9.2f %10.3f %10.3f\n", i, name, ms, r.plan.expanded, r.plan.length_m,
                  r.plan.min_clearance_m, r.plan.mean_clearance_m);
    }
  }
  std::printf("\nmean length ratio modified / plain: %.3f\n\n", ratio_sum / static_cast<double>(Queries().size()));
}

void BM_Costmap(benchmark::State& state) {
  CostmapOptions o = g_modified;
  for (auto _ : state) benchmark::DoNotOptimize(Costmap(Willow(), {}, o).step_factor(0));
}
BENCHMARK(BM_Costmap)->Unit(benchmark::kMillisecond);

// The daemon's costmap: the same with the 3D map's obstacle layer, here posts of 15 x 15 cm every 2 m wherever the
// map is free, without and with the guard's margin round them at a cost (discs stamped round the layer's edge cells).
void BM_CostmapWithLayer(benchmark::State& state) {
  const OccupancyGrid& map = Willow();
  std::vector<std::int8_t> layer(map.cells().size(), kFreeCell);
  for (int y = 0; y + 3 < map.height(); y += 40) {
    for (int x = 0; x + 3 < map.width(); x += 40) {
      for (int dy = 0; dy < 3; ++dy) {
        for (int dx = 0; dx < 3; ++dx) {
          if (map.at({x + dx, y + dy}) == kFreeCell)
            layer[static_cast<std::size_t>(y + dy) * map.width() + x + dx] = kOccupiedCell;
        }
      }
    }
  }
  CostmapOptions o = g_modified;
  if (state.range(0) == 0) o.layer_cost = 0.0;
  for (auto _ : state) benchmark::DoNotOptimize(Costmap(map, layer, {}, o).step_factor(0));
  state.SetLabel(state.range(0) == 0 ? "layer_cost 0 (no margin)" : "the guard's margin at a cost");
}
BENCHMARK(BM_CostmapWithLayer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_Plan(benchmark::State& state) {
  CostmapOptions o = g_modified;
  if (state.range(0) == 0) o.distance_weight = 0.0;
  const Costmap c(Willow(), {}, o);
  const Eigen::Vector2d s = Snap(c, Queries()[1].first);
  const Eigen::Vector2d g = Snap(c, Queries()[1].second);
  for (auto _ : state) benchmark::DoNotOptimize(PlanPath(c, s, g).plan.length_m);
  state.SetLabel(state.range(0) == 0 ? "plain A*" : "modified A*");
}
BENCHMARK(BM_Plan)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// People's ways on the planner: five people walking 10 m lines across the query's way for a minute.
TrafficMap WillowTraffic() {
  TrafficMap traffic(Willow(), TrafficOptions{});
  const Eigen::Vector2d from = Queries()[1].first;
  const Eigen::Vector2d to = Queries()[1].second;
  for (int k = 0; k < 600; ++k) {
    const double t = 0.1 * k;
    std::vector<TrackedObject> walkers;
    for (int i = 1; i <= 5; ++i) {
      TrackedObject o;
      o.position = from + (to - from) * (i / 6.0) + Eigen::Vector2d(0.0, std::fmod(0.8 * t, 10.0) - 5.0);
      o.velocity = {0.0, 0.8};
      o.moving = true;
      walkers.push_back(o);
    }
    traffic.Add(t, walkers);
  }
  return traffic;
}

// The tracking node's work every second: the traffic costs of the whole map.
void BM_TrafficStepCost(benchmark::State& state) {
  const TrafficMap traffic = WillowTraffic();
  for (auto _ : state) benchmark::DoNotOptimize(traffic.StepCost(60.0).data());
  state.SetLabel(std::to_string(Willow().width()) + " x " + std::to_string(Willow().height()) + " cells");
}
BENCHMARK(BM_TrafficStepCost)->Unit(benchmark::kMillisecond);

// The same query as BM_Plan's, with those costs added to every step.
void BM_PlanWithTraffic(benchmark::State& state) {
  const Costmap c(Willow(), {}, g_modified);
  const std::vector<float> cost = WillowTraffic().StepCost(60.0);
  PathOptions options;
  options.extra_cost = cost;
  const Eigen::Vector2d s = Snap(c, Queries()[1].first);
  const Eigen::Vector2d g = Snap(c, Queries()[1].second);
  for (auto _ : state) benchmark::DoNotOptimize(PlanPath(c, s, g, std::nullopt, nullptr, options).plan.length_m);
}
BENCHMARK(BM_PlanWithTraffic)->Unit(benchmark::kMillisecond);

// What a goal costs when the map has just changed: costmap and search together (the 50 ms budget).
void BM_CostmapAndPlan(benchmark::State& state) {
  for (auto _ : state) {
    const Costmap c(Willow(), {}, g_modified);
    benchmark::DoNotOptimize(PlanPath(c, Snap(c, Queries()[1].first), Snap(c, Queries()[1].second)).plan.length_m);
  }
}
BENCHMARK(BM_CostmapAndPlan)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace corridor::nav

int main(int argc, char** argv) {
  using corridor::nav::g_modified;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--weight") == 0) g_modified.distance_weight = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--saturation") == 0) g_modified.saturation_m = std::atof(argv[i + 1]);
  }
  corridor::nav::PrintComparison();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
