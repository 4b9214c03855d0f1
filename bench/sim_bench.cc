// The simulator's sensor cost in the default world (Willow Garage, walls extruded from the map).
// BM_RayPerCall is the baseline: the same depth-camera rays cast one Embree call each, in the same process,
// so the ratio to BM_DepthFan shows what batching buys on this machine whatever its load.
#include <benchmark/benchmark.h>

#include "drivers/sim/sensors.h"

namespace corridor::drivers::sim {
namespace {

const World& Willow() {
  static const World world = LoadWorld(
      std::string(CORRIDOR_SOURCE_DIR) + "/config/worlds/willow_garage/willow-full-0.05.yaml", WorldOptions{});
  return world;
}

const RayCaster& Caster() {
  static const RayCaster caster(Willow().mesh);
  return caster;
}

// The robot at the default start, looking down the corridor.
Eigen::Isometry3d CameraPose(const SimCameraOptions& o) {
  return nav::Pose2{24.38, 24.07, 1.5708}.ToIsometry3() * MakeCameraInfo(o).camera.base_T_camera;
}

SimCameraOptions Camera(int width, int height) {
  SimCameraOptions o;
  o.width = width;
  o.height = height;
  return o;
}

void BM_RenderRgbd(benchmark::State& state) {
  const SimCameraOptions o = Camera(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const RgbdRenderer renderer(Caster(), o);
  std::mt19937 rng(1);
  RgbdFrame frame;
  for (auto _ : state) {
    renderer.Render(CameraPose(o), rng, frame);
    benchmark::DoNotOptimize(frame.depth_mm.data);
  }
  state.SetItemsProcessed(state.iterations() * o.width * o.height);
}
BENCHMARK(BM_RenderRgbd)->Args({320, 240})->Args({640, 480})->Unit(benchmark::kMillisecond);

std::vector<Eigen::Vector3f> DepthRays(const SimCameraOptions& o) {
  const CameraInfo info = MakeCameraInfo(o);
  const Eigen::Matrix3f r = CameraPose(o).linear().cast<float>();
  std::vector<Eigen::Vector3f> rays;
  for (int v = 0; v < o.height; ++v) {
    for (int u = 0; u < o.width; ++u) {
      rays.push_back(r * Eigen::Vector3f(static_cast<float>((u + 0.5 - info.camera.cx) / info.camera.fx),
                                         static_cast<float>((v + 0.5 - info.camera.cy) / info.camera.fy), 1.0f));
    }
  }
  return rays;
}

void BM_DepthFan(benchmark::State& state) {
  const SimCameraOptions o = Camera(320, 240);
  const std::vector<Eigen::Vector3f> rays = DepthRays(o);
  std::vector<RayHit> hits(rays.size());
  const Eigen::Vector3f origin = CameraPose(o).translation().cast<float>();
  for (auto _ : state) {
    Caster().CastFan(origin, rays, 0.0f, 1e3f, hits);
    benchmark::DoNotOptimize(hits.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
}
BENCHMARK(BM_DepthFan)->Unit(benchmark::kMillisecond);

void BM_RayPerCall(benchmark::State& state) {
  const SimCameraOptions o = Camera(320, 240);
  const std::vector<Eigen::Vector3f> rays = DepthRays(o);
  std::vector<RayHit> hits(rays.size());
  const Eigen::Vector3f origin = CameraPose(o).translation().cast<float>();
  for (auto _ : state) {
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = Caster().Cast(origin, rays[i], 0.0f, 1e3f);
    benchmark::DoNotOptimize(hits.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
}
BENCHMARK(BM_RayPerCall)->Unit(benchmark::kMillisecond);

void BM_LaserScan(benchmark::State& state) {
  SimLaserOptions o;
  std::mt19937 rng(1);
  LaserScan scan;
  Eigen::Isometry3d pose = nav::Pose2{24.38, 24.07, 1.5708}.ToIsometry3();
  pose.translation().z() = o.mount_height_m;
  for (auto _ : state) {
    CastScan(Caster(), pose, o, rng, scan);
    benchmark::DoNotOptimize(scan.ranges.data());
  }
}
BENCHMARK(BM_LaserScan)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor::drivers::sim

BENCHMARK_MAIN();
