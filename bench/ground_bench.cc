// MORP ground segmentation per depth frame at VGA and 720p, against the budget of 0.5 ms (VGA) and 1 ms (720p) on one
// core, with the default lanes (ten across 1 m). Baselines in the same process: BM_PointCloud turns the whole frame
// into base-frame points, the first step of the point-cloud pipelines MORP is compared with; BM_VoxelObstacles is the
// scenario runner's whole comparison front end (cloud, voxel grid, obstacle extraction: nav/ground/voxel_obstacles.h).
#include <benchmark/benchmark.h>

#include "drivers/sim/sensors.h"
#include "nav/geometry/posed.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/morp.h"
#include "nav/ground/voxel_obstacles.h"

namespace corridor {
namespace {

struct Scene {
  drivers::sim::SimCameraOptions options;
  cv::Mat depth;
};

// A floor with a wall 2.5 m ahead and a box on the left at 1.5 m, rendered with the camera's noise and holes.
const Scene& SceneAt(int width, int height) {
  static std::map<std::pair<int, int>, Scene> scenes;
  auto& scene = scenes[{width, height}];
  if (scene.depth.empty()) {
    scene.options.width = width;
    scene.options.height = height;
    drivers::sim::TriangleMesh mesh;
    const Eigen::Vector3f grey(0.6f, 0.6f, 0.6f);
    mesh.AddBox({-5.0f, -10.0f, -0.01f}, {50.0f, 10.0f, 0.0f}, grey);
    mesh.AddBox({2.5f, -3.0f, 0.0f}, {2.7f, 3.0f, 1.5f}, grey);
    mesh.AddBox({1.5f, 0.0f, 0.0f}, {1.8f, 0.5f, 0.4f}, grey);
    const drivers::sim::RayCaster caster(mesh);
    const drivers::sim::RgbdRenderer renderer(caster, scene.options);
    std::mt19937 rng(1);
    drivers::RgbdFrame frame;
    renderer.Render(drivers::sim::MakeCameraInfo(scene.options).camera.base_T_camera, rng, frame);
    scene.depth = frame.depth_mm;
  }
  return scene;
}

void BM_Morp(benchmark::State& state) {
  const Scene& scene = SceneAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  nav::Morp morp(drivers::sim::MakeCameraInfo(scene.options).camera, nav::MorpOptions{});
  for (auto _ : state) benchmark::DoNotOptimize(morp.Process(scene.depth).data());
}
BENCHMARK(BM_Morp)->Args({640, 480})->Args({1280, 720})->Unit(benchmark::kMicrosecond);

void BM_PointCloud(benchmark::State& state) {
  const Scene& scene = SceneAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const nav::PinholeCamera camera = drivers::sim::MakeCameraInfo(scene.options).camera;
  const Eigen::Matrix3f rotation = camera.base_T_camera.linear().cast<float>();
  const Eigen::Vector3f origin = camera.base_T_camera.translation().cast<float>();
  std::vector<Eigen::Vector3f> cloud;
  cloud.reserve(scene.depth.total());
  for (auto _ : state) {
    cloud.clear();
    for (int v = 0; v < scene.depth.rows; ++v) {
      const auto* row = scene.depth.ptr<std::uint16_t>(v);
      for (int u = 0; u < scene.depth.cols; ++u) {
        if (row[u] == 0) continue;
        const float d = row[u] * 0.001f;
        cloud.push_back(origin + rotation * Eigen::Vector3f(static_cast<float>((u - camera.cx) / camera.fx) * d,
                                                            static_cast<float>((v - camera.cy) / camera.fy) * d, d));
      }
    }
    benchmark::DoNotOptimize(cloud.data());
  }
}
BENCHMARK(BM_PointCloud)->Args({640, 480})->Args({1280, 720})->Unit(benchmark::kMicrosecond);

void BM_VoxelObstacles(benchmark::State& state) {
  const Scene& scene = SceneAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  nav::VoxelObstacles voxels(drivers::sim::MakeCameraInfo(scene.options).camera, nav::VoxelObstacleOptions{});
  for (auto _ : state) benchmark::DoNotOptimize(voxels.Process(scene.depth).data());
}
BENCHMARK(BM_VoxelObstacles)->Args({640, 480})->Args({1280, 720})->Unit(benchmark::kMicrosecond);

// A camera on a pan servo (nav/geometry/posed.h): the control path's two readers of a frame, MORP and the obstacle
// memory's depth scan, each frame from a pose of its own (the camera turning: both rebuilt every frame) against the
// same frames from one pose (range(2) 0: the camera still). The frame is the same: this is the rebuilding's cost.
void BM_PannedFrame(benchmark::State& state) {
  const Scene& scene = SceneAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const bool turning = state.range(2) != 0;
  const nav::PinholeCamera camera = drivers::sim::MakeCameraInfo(scene.options).camera;
  nav::Posed<nav::Morp> morp;
  morp.Reset(camera,
             [](std::optional<nav::Morp>& r, const nav::PinholeCamera& c) { r.emplace(c, nav::MorpOptions{}); });
  nav::Posed<nav::DepthScan> scan;
  scan.Reset(camera, [](std::optional<nav::DepthScan>& r, const nav::PinholeCamera& c) {
    r.emplace(c, nav::ForObstacleMemory(nav::DepthScanOptions{}));
  });
  int frame = 0;
  for (auto _ : state) {
    // Each frame 0.01 rad from the last (any turn of more than 0.1 mrad rebuilds).
    const double pan = turning ? 0.01 * (frame++ % 20) : 0.0;
    const Eigen::Isometry3d pose = nav::PanTurn({0.1, 0.0}, pan) * camera.base_T_camera;
    benchmark::DoNotOptimize(morp.At(pose).Process(scene.depth).data());
    benchmark::DoNotOptimize(scan.At(pose).Process(scene.depth).data());
  }
}
BENCHMARK(BM_PannedFrame)
    ->Args({320, 240, 0})
    ->Args({320, 240, 1})
    ->Args({640, 480, 0})
    ->Args({640, 480, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor

BENCHMARK_MAIN();
