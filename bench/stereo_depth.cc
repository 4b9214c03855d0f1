// Not a Google Benchmark: ASNS's Table 11 on the simulated stereo camera (docs/asns.md). A room of textured walls and
// boxes (testing/stereo_room.h) is seen from `--poses` poses by the stereo pair and, without noise, by the depth
// sensor's renderer (the truth); for each band of true depth, on the walls and boxes (not the floor), the share of
// pixels with a depth, the median error and the share more than 4 cm off; then the depth path's time per pair
// (rectify, match, depth) on one core.
//   build/bench/stereo_depth [--baseline-m 0.12] [--width 320] [--disparities 80] [--poses 40]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "drivers/sim/sim_stereo.h"
#include "testing/stereo_room.h"

namespace {

using corridor::drivers::RgbdFrame;
using namespace corridor::drivers::sim;

double Option(int argc, char** argv, const std::string& name, double fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (name == argv[i]) return std::atof(argv[i + 1]);
  }
  return fallback;
}

double Median(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const double baseline_m = Option(argc, argv, "--baseline-m", 0.12);
  const int poses = static_cast<int>(Option(argc, argv, "--poses", 40));
  SimCameraOptions camera;
  camera.width = static_cast<int>(Option(argc, argv, "--width", 320));
  camera.height = camera.width * 3 / 4;
  SimStereoOptions stereo;
  stereo.depth.matcher.disparities = static_cast<int>(Option(argc, argv, "--disparities", 80));
  SimCameraOptions exact = StereoViewOptions(camera);
  exact.noise_a_m = exact.noise_b_per_m = exact.dropout_fraction = 0.0;

  const TriangleMesh mesh = corridor::testing::StereoRoom();
  const RayCaster caster(mesh);
  const RgbdRenderer truth(caster, exact);
  // The pair as SimStereoCamera renders it, its depth path timed on its own.
  const RgbdRenderer views(caster, StereoViewOptions(camera));
  const Eigen::Isometry3d base_T_left = MakeCameraInfo(camera).camera.base_T_camera;
  corridor::drivers::stereo::StereoDepthOptions depth_options = stereo.depth;
  depth_options.width = camera.width;
  corridor::drivers::stereo::StereoDepth depth(IdealStereoCalibration(camera, baseline_m), base_T_left, depth_options);
  const corridor::nav::PinholeCamera& k = depth.info().camera;
  cv::Mat left, right;

  struct Band {
    long pixels = 0;
    long found = 0;
    long off = 0;  // more than 4 cm
    std::vector<double> errors_m;
  };
  std::map<int, Band> bands;  // by 0.5 m of true depth
  std::mt19937 rng(5);
  double process_s = 0.0;
  for (int n = 0; n < poses; ++n) {
    const Eigen::Isometry3d pose = corridor::testing::StereoRoomPose(n, poses);
    RgbdFrame measured, exact_frame;
    const Eigen::Isometry3d world_T_left = pose * base_T_left;
    views.RenderColor(world_T_left, stereo.texture, stereo.image_noise, rng, left);
    views.RenderColor(world_T_left * Eigen::Translation3d(baseline_m, 0.0, 0.0), stereo.texture, stereo.image_noise,
                      rng, right);
    const auto start = std::chrono::steady_clock::now();
    depth.Process(left, right, measured);
    process_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    truth.Render(pose * k.base_T_camera, rng, exact_frame);
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const double z = exact_frame.depth_mm.at<std::uint16_t>(v, u) * 1e-3;
        if (z < 0.5 || z >= 5.0) continue;
        const Eigen::Vector3d world = pose * k.base_T_camera * (k.Ray(u, v) * z);
        if (world.z() < 0.01) continue;  // the floor: seen at a grazing angle, not what Table 11 measures
        Band& band = bands[static_cast<int>(z * 2.0)];
        ++band.pixels;
        const double d = measured.depth_mm.at<std::uint16_t>(v, u) * 1e-3;
        if (d <= 0.0) continue;
        ++band.found;
        band.errors_m.push_back(std::abs(d - z));
        band.off += std::abs(d - z) > 0.04 ? 1 : 0;
      }
    }
  }
  std::printf("baseline %.2f m, %d x %d, %d disparities, %d poses\n\n", baseline_m, k.width, k.height,
              stereo.depth.matcher.disparities, poses);
  std::printf("| true depth | pixels | with depth | median error | more than 4 cm off |\n|---|---|---|---|---|\n");
  for (auto& [key, band] : bands) {
    std::printf("| %.1f-%.1f m | %ld | %.1f %% | %.1f cm | %.1f %% |\n", key / 2.0, key / 2.0 + 0.5, band.pixels,
                100.0 * band.found / band.pixels, 100.0 * Median(band.errors_m),
                band.found > 0 ? 100.0 * band.off / band.found : 0.0);
  }
  std::printf("\nthe depth path (rectify, match, depth): %.1f ms a pair\n", 1000.0 * process_s / poses);
  return 0;
}
