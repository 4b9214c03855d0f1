// OctoMap insertion of one 320 x 240 depth frame (issue 20's timed figure), in the default world (Willow Garage)
// with the simulator's noise, the robot walking down the start corridor so the tree already holds what it saw. The
// argument is the pixel step (1: every pixel; 2, the daemon's default: every other pixel of every other row). The
// projection onto the map's grid (the planner's layer) is timed beside it. Results: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include "drivers/sim/sensors.h"
#include "nav/mapping/occupancy_octree.h"

namespace corridor {
namespace {

using drivers::sim::WorldOptions;

const drivers::sim::World& Willow() {
  static const drivers::sim::World world = drivers::sim::LoadWorld(
      std::string(CORRIDOR_SOURCE_DIR) + "/config/worlds/willow_garage/willow-full-0.05.yaml", WorldOptions{});
  return world;
}

struct Frames {
  nav::PinholeCamera camera;
  std::vector<nav::Pose2> poses;
  std::vector<cv::Mat> depth;
};

// 40 frames 0.1 m apart from the default start, looking down the corridor.
const Frames& Walk() {
  static const Frames frames = [] {
    Frames f;
    drivers::sim::SimCameraOptions options;
    options.width = 320;
    options.height = 240;
    f.camera = drivers::sim::MakeCameraInfo(options).camera;
    const drivers::sim::RayCaster caster(Willow().mesh);
    const drivers::sim::RgbdRenderer renderer(caster, options);
    std::mt19937 rng(1);
    for (int i = 0; i < 40; ++i) {
      const nav::Pose2 pose{24.38, 24.07 + 0.1 * i, 1.5708};
      drivers::RgbdFrame frame;
      renderer.Render(pose.ToIsometry3() * f.camera.base_T_camera, rng, frame);
      f.poses.push_back(pose);
      f.depth.push_back(frame.depth_mm);
    }
    return f;
  }();
  return frames;
}

void BM_OctreeInsert(benchmark::State& state) {
  const Frames& frames = Walk();
  nav::OccupancyOctreeOptions options;
  options.pixel_step = static_cast<int>(state.range(0));
  nav::OccupancyOctree octree(options);
  std::size_t i = 0;
  for (auto _ : state) {
    octree.InsertDepth(frames.depth[i], frames.camera, frames.poses[i]);
    i = (i + 1) % frames.depth.size();
  }
  state.counters["leaves"] = static_cast<double>(octree.leaf_count());
  state.counters["MB"] = static_cast<double>(octree.memory_bytes()) / 1e6;
}
BENCHMARK(BM_OctreeInsert)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_OctreeProject(benchmark::State& state) {
  const Frames& frames = Walk();
  nav::OccupancyOctree octree;
  for (std::size_t i = 0; i < frames.depth.size(); ++i)
    octree.InsertDepth(frames.depth[i], frames.camera, frames.poses[i]);
  const nav::OccupancyGrid& map = *Willow().source_map;
  for (auto _ : state) benchmark::DoNotOptimize(octree.ProjectOccupied(map, 0.1, 1.2).data());
}
BENCHMARK(BM_OctreeProject)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace corridor

BENCHMARK_MAIN();
