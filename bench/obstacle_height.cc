// Not a Google Benchmark: ASNS's Table 13 on the simulator (docs/asns.md). A box alone on a large floor, straight
// ahead of the camera at 1 to 5.3 m (its face within 5.5 m of the robot), 10, 20 and 50 cm high (the camera is 30 cm
// up: the lower two show their tops near by), is seen by the depth sensor, by the narrow stereo pair and by ASNS's
// camera (the narrow and wide pairs fused and filtered over frames, MMSVF: measured from its second frame on); AFDS
// (nav/ground/afds.h) at three region grids measures the tallest obstacle in the frame, and the error against the
// box's height is averaged by distance band (under 3 m and 3 to 5.5 m, the paper's). A box it does not find (no
// obstacle at all) counts as missed, not in the errors. Then AFDS's time per frame at each grid on one core.
//   build/bench/obstacle_height [--frames 4] [--detail: every measurement on stderr]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/sim/sim_stereo.h"
#include "nav/ground/afds.h"
#include "nav/ground/multi_view.h"
#include "testing/stereo_room.h"
#include "tools/common/command_line.h"

namespace {

using corridor::drivers::RgbdFrame;
using namespace corridor::drivers::sim;
using corridor::nav::Afds;
using corridor::nav::AfdsCell;
using corridor::nav::AfdsOptions;

enum class Sensor { kDepth, kStereo, kMmsvf };

const char* Name(Sensor sensor) {
  switch (sensor) {
    case Sensor::kDepth: return "depth sensor";
    case Sensor::kStereo: return "stereo, 12 cm";
    case Sensor::kMmsvf: return "stereo, MMSVF (12 + 24 cm, 2 of 3 frames)";
  }
  return "";
}

struct Band {
  double sum_error_m = 0.0;
  double max_error_m = 0.0;
  int measured = 0;
  int missed = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 4;
  bool detail = false;
  try {
    corridor::tools::Arguments args(argc, argv);
    while (args.Next()) {
      if (args.current() == "--detail") {
        detail = true;
      } else if (args.current() == "--frames") {
        frames = static_cast<int>(corridor::tools::ParseNumber(args.current(), args.Value(), 1, 1000));
      } else {
        throw std::invalid_argument("unknown option " + args.current());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obstacle_height: %s\n", e.what());
    return 2;
  }
  const std::vector<std::pair<int, int>> grids = {{3, 2}, {6, 4}, {12, 9}};
  const std::vector<float> heights = {0.1f, 0.2f, 0.5f};
  const std::vector<float> distances = {1.0f, 1.5f, 2.0f, 2.5f, 3.0f, 3.5f, 4.0f, 4.5f, 5.0f, 5.3f};
  const SimCameraOptions camera;  // the simulator's default: 320 x 240, 0.3 m up, tilted 10 degrees
  SimStereoOptions stereo;
  stereo.enabled = true;
  SimStereoOptions mmsvf = stereo;
  mmsvf.wide_baseline_m = 0.24;

  std::printf("AFDS's obstacle height error, %d frames per box and distance, boxes 10, 20 and 50 cm high\n\n", frames);
  std::printf("| sensor | grid | mean error under 3 m | max | mean error 3-5.5 m | max | missed |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::vector<double> time_ms(grids.size(), 0.0);
  int timed = 0;
  for (const Sensor sensor : {Sensor::kDepth, Sensor::kStereo, Sensor::kMmsvf}) {
    const bool use_stereo = sensor != Sensor::kDepth;
    std::vector<Band> near(grids.size()), far(grids.size());
    for (const float height : heights) {
      for (const float distance : distances) {
        const TriangleMesh mesh = corridor::testing::BoxAhead(distance, 0.3f, height);
        const RayCaster caster(mesh);
        const RgbdRenderer depth_sensor(caster, camera);
        SimStereoCamera pair(caster, camera, sensor == Sensor::kMmsvf ? mmsvf : stereo);
        const corridor::nav::PinholeCamera k = use_stereo ? pair.info().camera : MakeCameraInfo(camera).camera;
        corridor::nav::MultiViewFilter filter(k, corridor::nav::MultiViewOptions{});
        std::mt19937 rng(static_cast<unsigned>(1000 * distance + 100 * height));
        for (int f = sensor == Sensor::kMmsvf ? -1 : 0; f < frames; ++f) {
          RgbdFrame frame;
          if (use_stereo) {
            pair.Render(Eigen::Isometry3d::Identity(), rng, frame);
          } else {
            depth_sensor.Render(k.base_T_camera, rng, frame);
          }
          if (sensor == Sensor::kMmsvf) {
            filter.Apply(frame.depth_mm, corridor::nav::Pose2{});
            if (f < 0) continue;  // the filter's first frame: nothing beyond 1 m seen twice yet
          }
          for (std::size_t g = 0; g < grids.size(); ++g) {
            AfdsOptions options;
            options.grid_columns = grids[g].first;
            options.grid_rows = grids[g].second;
            Afds afds(k, options, corridor::nav::MorpOptions{});
            const auto start = std::chrono::steady_clock::now();
            const auto& out = afds.Process(frame.depth_mm);
            if (!use_stereo)
              time_ms[g] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            double tallest = 0.0;
            for (const AfdsCell& cell : out.cells) tallest = std::max(tallest, cell.obstacle_height_m);
            if (detail) {
              std::fprintf(stderr, "%s %dx%d: %.2f m high at %.1f m: %.3f\n", Name(sensor), grids[g].first,
                           grids[g].second, height, distance, tallest);
            }
            Band& band = distance < 3.0f ? near[g] : far[g];
            if (tallest <= 0.0) {
              ++band.missed;
              continue;
            }
            const double error = std::abs(tallest - height);
            band.sum_error_m += error;
            band.max_error_m = std::max(band.max_error_m, error);
            ++band.measured;
          }
          timed += use_stereo ? 0 : 1;
        }
      }
    }
    for (std::size_t g = 0; g < grids.size(); ++g) {
      std::printf("| %s | %d x %d | %.2f cm | %.1f cm | %.2f cm | %.1f cm | %d of %d |\n", Name(sensor), grids[g].first,
                  grids[g].second, 100.0 * near[g].sum_error_m / std::max(1, near[g].measured),
                  100.0 * near[g].max_error_m, 100.0 * far[g].sum_error_m / std::max(1, far[g].measured),
                  100.0 * far[g].max_error_m, near[g].missed + far[g].missed,
                  near[g].measured + far[g].measured + near[g].missed + far[g].missed);
    }
  }
  std::printf("\nAFDS's time a frame (depth sensor, 320 x 240):");
  for (std::size_t g = 0; g < grids.size(); ++g) {
    std::printf(" %d x %d %.1f ms;", grids[g].first, grids[g].second, time_ms[g] / std::max(1, timed));
  }
  std::printf("\n");
  return 0;
}
