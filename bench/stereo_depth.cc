// Not a Google Benchmark: ASNS's Table 11 on the simulated stereo camera (docs/asns.md). A room of textured walls and
// boxes (testing/stereo_room.h) is seen from `--poses` poses by the stereo pair and, without noise, by the depth
// sensor's renderer (the truth); for each band of true depth, on the walls and boxes (not the floor), the share of
// pixels with a depth, the median error and the share more than 4 cm off; then the depth path's time per pair
// (rectify, match, depth) on one core.
//   build/bench/stereo_depth [--baseline-m 0.12] [--width 320] [--disparities 80] [--poses 40]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/sim/sim_stereo.h"
#include "testing/stereo_room.h"
#include "tools/common/command_line.h"

namespace {

using corridor::drivers::RgbdFrame;
using corridor::tools::Arguments;
using corridor::tools::ParseNumber;
using namespace corridor::drivers::sim;

double Median(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  double baseline_m = 0.12;
  int poses = 40;
  SimCameraOptions camera;
  SimStereoOptions stereo;
  try {
    Arguments args(argc, argv);
    while (args.Next()) {
      const std::string& flag = args.current();
      const auto number = [&](double lo, double hi) { return ParseNumber(flag, args.Value(), lo, hi); };
      if (flag == "--baseline-m") {
        baseline_m = number(0.01, 1.0);
      } else if (flag == "--poses") {
        poses = static_cast<int>(number(1, 10000));
      } else if (flag == "--width") {
        camera.width = static_cast<int>(number(64, 4096));
      } else if (flag == "--disparities") {
        stereo.depth.matcher.disparities = static_cast<int>(number(16, 1024));
      } else {
        throw std::invalid_argument("unknown option " + flag);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereo_depth: %s\n", e.what());
    return 2;
  }
  camera.height = camera.width * 3 / 4;
  stereo.baseline_m = baseline_m;
  stereo.depth.width = camera.width;  // matched at the views' size
  SimCameraOptions exact = StereoViewOptions(camera);
  exact.noise_a_m = exact.noise_b_per_m = exact.dropout_fraction = 0.0;

  const TriangleMesh mesh = corridor::testing::StereoRoom();
  const RayCaster caster(mesh);
  const RgbdRenderer truth(caster, exact);
  SimStereoCamera pair(caster, camera, stereo);
  const corridor::nav::PinholeCamera& k = pair.info().camera;

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
    pair.RenderViews(pose, rng);
    const auto start = std::chrono::steady_clock::now();
    pair.Match(measured);
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
