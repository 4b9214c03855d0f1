// Not a Google Benchmark: ASNS's Table 12 on the simulator (docs/asns.md): how many frames a stereo camera takes to
// detect an obstacle 2.5 to 3.5 m ahead, textured and untextured. A box 40 cm wide and 50 cm high stands on a large
// floor before the robot, which stands still; frames come one after another, each with its own sensor noise. An
// obstacle is detected when the depth scan the robot's obstacle memory takes (nav/ground/depth_scan.h, out to 4 m)
// has points on it (or within 20 cm of it: block matching fattens an obstacle's sides against a far background by
// half a block) in at least 3 columns. "Phantoms" are that scan's points anywhere else (there is nothing else but the
// floor), counted from the third frame on (once the filter has its window): what a filter is for. Cameras: the narrow
// pair (12 cm) as it is, and ASNS's MMSVF (the narrow and wide pairs fused, drivers/stereo/multi_baseline.h, then
// filtered over frames, nav/ground/multi_view.h).
//   build/bench/detection_frames [--trials 10] [--frames 10]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/sim/sim_stereo.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/multi_view.h"
#include "testing/stereo_room.h"
#include "tools/common/command_line.h"

namespace {

using corridor::drivers::RgbdFrame;
using namespace corridor::drivers::sim;

constexpr float kHalfWidthM = 0.2f;
constexpr float kHeightM = 0.5f;

struct Result {
  std::vector<int> frames;  // per trial: the frame (1-based) it was first detected in; 0: never
  long phantoms = 0;        // scan points off the box, over the frames from the third on
  int counted = 0;          // those frames
  int scanned = 0;          // every frame
  double ms = 0.0;          // the depth path and filter, per frame
  double filter_ms = 0.0;   // the filter alone, per frame
};

Result Measure(float distance_m, bool textured, bool mmsvf, int trials, int frames) {
  const TriangleMesh mesh = corridor::testing::BoxAhead(distance_m, kHalfWidthM, kHeightM);
  const RayCaster caster(mesh);
  const SimCameraOptions camera;  // the simulator's: 320 x 240, 0.3 m up, tilted 10 degrees
  SimStereoOptions stereo;
  stereo.enabled = true;
  stereo.texture = textured ? 0.5 : 0.0;
  if (mmsvf) stereo.wide_baseline_m = 0.24;
  SimStereoCamera pair(caster, camera, stereo);
  const corridor::nav::PinholeCamera& k = pair.info().camera;
  corridor::nav::DepthScan scan(k, corridor::nav::DepthScanOptions{});
  constexpr double kMarginM = 0.2;
  const double near_x = distance_m + 0.1 - kMarginM;
  const double far_x = distance_m + 0.5 + kMarginM;
  Result result;
  for (int trial = 0; trial < trials; ++trial) {
    std::mt19937 rng(static_cast<unsigned>(7919 * trial + 1000 * distance_m + (textured ? 1 : 2)));
    corridor::nav::MultiViewOptions options;
    options.enabled = true;
    corridor::nav::MultiViewFilter filter(k, options);
    int detected = 0;
    for (int f = 1; f <= frames; ++f) {
      RgbdFrame frame;
      pair.RenderViews(Eigen::Isometry3d::Identity(), rng);
      const auto start = std::chrono::steady_clock::now();
      pair.Match(frame);
      const auto matched = std::chrono::steady_clock::now();
      if (mmsvf) filter.Apply(frame.depth_mm, corridor::nav::Pose2{});
      const auto end = std::chrono::steady_clock::now();
      result.ms += std::chrono::duration<double, std::milli>(end - start).count();
      result.filter_ms += std::chrono::duration<double, std::milli>(end - matched).count();
      ++result.scanned;
      int on_box = 0;
      for (const Eigen::Vector2d& p : scan.Process(frame.depth_mm)) {
        const bool box = p.x() >= near_x && p.x() <= far_x && std::abs(p.y()) <= kHalfWidthM + kMarginM;
        on_box += box ? 1 : 0;
        result.phantoms += box || f < 3 ? 0 : 1;
      }
      result.counted += f < 3 ? 0 : 1;
      if (on_box >= 3 && detected == 0) detected = f;
    }
    result.frames.push_back(detected);
  }
  result.ms /= std::max(1, result.scanned);
  result.filter_ms /= std::max(1, result.scanned);
  return result;
}

// The multi-view filter's time a frame where much is seen: the stereo room (testing/stereo_room.h) walked across
// in 200 frames with MMSVF's camera; the 50th and 99th percentiles, one core.
void FilterTimeInARoom() {
  const TriangleMesh mesh = corridor::testing::StereoRoom();
  const RayCaster caster(mesh);
  SimStereoOptions stereo;
  stereo.enabled = true;
  stereo.wide_baseline_m = 0.24;
  SimStereoCamera pair(caster, SimCameraOptions{}, stereo);
  corridor::nav::MultiViewFilter filter(pair.info().camera, corridor::nav::MultiViewOptions{});
  std::mt19937 rng(3);
  std::vector<double> ms;
  long readings = 0;
  constexpr int kFrames = 200;
  for (int n = 0; n < kFrames; ++n) {
    const Eigen::Isometry3d pose = corridor::testing::StereoRoomPose(n, kFrames);
    RgbdFrame frame;
    pair.Render(pose, rng, frame);
    readings += cv::countNonZero(frame.depth_mm);
    const corridor::nav::Pose2 odom{pose.translation().x(), pose.translation().y(),
                                    std::atan2(pose.linear()(1, 0), pose.linear()(0, 0))};
    const auto start = std::chrono::steady_clock::now();
    filter.Apply(frame.depth_mm, odom);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  std::printf(
      "\nThe multi-view filter in the stereo room (%ld readings a frame, %zu cells kept): p50 %.2f ms, p99 %.2f "
      "ms, max %.2f ms a frame\n",
      readings / kFrames, filter.cells(), ms[ms.size() / 2], ms[ms.size() * 99 / 100], ms.back());
}

}  // namespace

int main(int argc, char** argv) {
  int trials = 10;
  int frames = 10;
  try {
    corridor::tools::Arguments args(argc, argv);
    while (args.Next()) {
      if (args.current() == "--trials") {
        trials = static_cast<int>(corridor::tools::ParseNumber(args.current(), args.Value(), 1, 1000));
      } else if (args.current() == "--frames") {
        frames = static_cast<int>(corridor::tools::ParseNumber(args.current(), args.Value(), 1, 1000));
      } else {
        throw std::invalid_argument("unknown option " + args.current());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detection_frames: %s\n", e.what());
    return 2;
  }
  std::printf("Frames to detect a 40 x 50 cm box (the robot still), %d trials of at most %d frames\n\n", trials,
              frames);
  std::printf(
      "| camera | surfaces | distance | frames: mean | max | never | phantom points a frame | ms a frame | "
      "filter's ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const bool mmsvf : {false, true}) {
    for (const bool textured : {true, false}) {
      for (const float distance : {2.5f, 3.0f, 3.5f}) {
        const Result r = Measure(distance, textured, mmsvf, trials, frames);
        int found = 0, sum = 0, worst = 0;
        for (int f : r.frames) {
          if (f == 0) continue;
          ++found;
          sum += f;
          worst = std::max(worst, f);
        }
        std::printf("| %s | %s | %.1f m | %.1f | %d | %d of %d | %.2f | %.1f | %.1f |\n",
                    mmsvf ? "MMSVF (12 + 24 cm, 2 of 3 frames)" : "narrow pair (12 cm)",
                    textured ? "textured" : "plain", distance, found > 0 ? static_cast<double>(sum) / found : 0.0,
                    worst, trials - found, trials, static_cast<double>(r.phantoms) / std::max(1, r.counted), r.ms,
                    r.filter_ms);
      }
    }
  }
  FilterTimeInARoom();
  return 0;
}
