// corridor-slam-eval: corridor's localization and mapping (nav/localization) on a CARMEN laser log, scored against
// the log's corrected poses. See --help, and docs/benchmarks.md for results.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "nav/localization/carmen_log.h"
#include "nav/localization/graph_slam.h"
#include "nav/localization/monte_carlo.h"
#include "nav/localization/trajectory_error.h"
#include "nav/map/map_io.h"
#include "tools/common/command_line.h"
#include "tools/slam_eval/heading_noise.h"
#include "tools/slam_eval/odometry_noise.h"

namespace {

using namespace corridor;
using nav::Pose2;
using tools::ParseNumber;

constexpr const char* kUsage = R"(usage: corridor-slam-eval LOG [options]

Runs corridor's localization and mapping on a CARMEN log (.log or .log.gz) of a robot with a front laser (FLASER).
"Corrected" logs carry no raw odometry, so the tool drives its own along the corrected poses, with seeded noise and
bias (defaults: 5 % of each move's length and 2 degrees per radian turned as noise, lengths read 2 % long, 1 degree
of heading lost per metre), and scores the estimate against the corrected poses.

  --mode slam         (default) build the map from the scans and the odometry; score by relative pose error:
                      local, over every pair of scans at most 2 m apart in travel, and revisit, over pairs within
                      1 m of each other after at least 10 m of travel between them
  --mode localize     build a reference map from the corrected poses, then localize in it with the odometry from the
                      first corrected pose; score each pose's error
  --global            (localize) start from nothing: relocalize globally, and report the time until converged
                      (the first of ten scans in a row within 0.2 m and 5 degrees); the error is scored from then
  --seed N            of the odometry noise (and the particle filter), default 1
  --odom-noise K      the noise and bias above times K, default 1 (0: perfect odometry)
  --scans N           only the first N scans
  --max-range M       readings at or beyond M metres are no return, default 25
  --fov-deg D         the laser's field of view, default 180
  --reference-noise   (slam) also estimate how noisy the corrected poses are themselves: the heading change between
                      consecutive scans by the corrected poses, by SLAM and by matching the two scans alone, separated
                      by the three-cornered hat (an upper bound for the corrected poses, see heading_noise.h)
  --json              the results as JSON on stdout
  --png FILE          the map (slam: as built; localize: the reference map) as an image
  --trajectory FILE   the estimated pose of every scan: "index timestamp x y theta" per line
  --help
)";

struct Options {
  std::string log;
  bool localize = false;
  bool global = false;
  std::uint64_t seed = 1;
  double odom_noise = 1.0;
  long scans = -1;
  bool reference_noise = false;
  double max_range_m = 25.0;
  double fov_deg = 180.0;
  bool json = false;
  std::string png;
  std::string trajectory;
};

Options ParseOptions(int argc, char** argv) {
  Options o;
  for (tools::Arguments args(argc, argv, 1); args.Next();) {
    const std::string arg = args.current();
    const auto value = [&] { return args.Value(); };
    if (arg == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--mode") {
      const std::string mode = value();
      if (mode != "slam" && mode != "localize")
        throw std::invalid_argument("--mode: slam or localize, got '" + mode + "'");
      o.localize = mode == "localize";
    } else if (arg == "--global") {
      o.global = true;
    } else if (arg == "--seed") {
      o.seed = static_cast<std::uint64_t>(ParseNumber(arg, value(), 0, 1e15));
    } else if (arg == "--odom-noise") {
      o.odom_noise = ParseNumber(arg, value(), 0, 100);
    } else if (arg == "--scans") {
      o.scans = static_cast<long>(ParseNumber(arg, value(), 2, 1e9));
    } else if (arg == "--max-range") {
      o.max_range_m = ParseNumber(arg, value(), 0.5, 1000);
    } else if (arg == "--fov-deg") {
      o.fov_deg = ParseNumber(arg, value(), 1, 360);
    } else if (arg == "--reference-noise") {
      o.reference_noise = true;
    } else if (arg == "--json") {
      o.json = true;
    } else if (arg == "--png") {
      o.png = value();
    } else if (arg == "--trajectory") {
      o.trajectory = value();
    } else if (!arg.empty() && arg[0] != '-' && o.log.empty()) {
      o.log = arg;
    } else {
      throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    }
  }
  if (o.log.empty()) throw std::invalid_argument("no log given (see --help)");
  if (o.global && !o.localize) throw std::invalid_argument("--global: only with --mode localize");
  if (o.reference_noise && o.localize) throw std::invalid_argument("--reference-noise: only with --mode slam");
  return o;
}

nlohmann::json ToJson(const nav::RelativeError& e) {
  const auto stats = [](const nav::ErrorStats& s) {
    return nlohmann::json{{"mean", s.mean}, {"std", s.std}, {"max", s.max}, {"rmse", s.rmse}, {"pairs", s.count}};
  };
  return {{"translation_m", stats(e.translation_m)}, {"rotation_deg", stats(e.rotation_deg)}};
}

std::string Row(const std::string& name, const nav::RelativeError& e) {
  char line[200];
  std::snprintf(line, sizeof line,
                "  %-18s translation %.4f +- %.4f m (max %.3f)   rotation %.3f +- %.3f deg (max %.2f)", name.c_str(),
                e.translation_m.mean, e.translation_m.std, e.translation_m.max, e.rotation_deg.mean, e.rotation_deg.std,
                e.rotation_deg.max);
  return line;
}

nav::RangeScan ToScan(const nav::CarmenScan& s, double max_range_m) {
  nav::RangeLimits limits;
  limits.max_range_m = max_range_m;
  return nav::ScanFromRanges(Pose2{}, s.angle_min_rad, s.angle_increment_rad, s.ranges_m, limits);
}

// The map made from the scans at the corrected poses: the reference that localization runs in.
nav::OccupancyGrid ReferenceMap(const nav::CarmenLog& log, const std::vector<Pose2>& truth, double max_range_m) {
  std::vector<nav::RangeScan> scans;
  scans.reserve(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) scans.push_back(ToScan(log.scans[i], max_range_m));
  std::vector<const nav::RangeScan*> pointers;
  for (const nav::RangeScan& s : scans) pointers.push_back(&s);
  return nav::RenderScans(pointers, truth, 0.05);
}

void WriteTrajectory(const std::string& path, const nav::CarmenLog& log, const std::vector<Pose2>& poses) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  char line[160];
  for (std::size_t i = 0; i < poses.size(); ++i) {
    std::snprintf(line, sizeof line, "%zu %.6f %.6f %.6f %.6f\n", i, log.scans[i].timestamp_s, poses[i].x_m,
                  poses[i].y_m, poses[i].yaw_rad);
    out << line;
  }
  if (!out) throw std::runtime_error(path + ": cannot write");
}

// The heading change between consecutive scans by the corrected poses, by SLAM, and by matching each scan into a
// field of the one before alone (guessed by the odometry), through the three-cornered hat; in degrees.
tools::HatSigmas ConsecutiveHeadingNoise(const nav::CarmenLog& log, const std::vector<Pose2>& truth,
                                         const std::vector<Pose2>& slam, const std::vector<Pose2>& odometry,
                                         double max_range_m) {
  std::vector<double> reference;
  std::vector<double> mapped;
  std::vector<double> matched;
  for (std::size_t i = 1; i < log.scans.size(); ++i) {
    nav::HitField before;
    before.Insert(ToScan(log.scans[i - 1], max_range_m), Pose2{});
    const std::vector<Eigen::Vector2f> points = nav::VoxelFilter(ToScan(log.scans[i], max_range_m).hits, 0.05);
    const Pose2 guess = odometry[i - 1].Inverse() * odometry[i];
    const nav::ScanMatch coarse = nav::CorrelativeMatch(before, points, guess, nav::SearchWindow{0.2, 0.1});
    const Pose2 match =
        nav::RefineMatch(before, points, coarse.pose, coarse.pose, nav::RefineOptions{1.0, 0.0, 0.0, 30});
    reference.push_back((truth[i - 1].Inverse() * truth[i]).yaw_rad);
    mapped.push_back((slam[i - 1].Inverse() * slam[i]).yaw_rad);
    matched.push_back(match.yaw_rad);
  }
  tools::HatSigmas s = tools::ThreeCorneredHat(reference, mapped, matched);
  for (double* v : {&s.a, &s.b, &s.c}) *v *= 180.0 / std::numbers::pi;
  return s;
}

void WritePng(const std::string& path, const nav::OccupancyGrid& map) {
  if (!cv::imwrite(path, nav::GridToImage(map))) throw std::runtime_error(path + ": cannot write the image");
}

int Run(const Options& o) {
  nav::CarmenLog log = nav::ReadCarmenLog(o.log, o.fov_deg * std::numbers::pi / 180.0);
  if (o.scans > 0 && static_cast<std::size_t>(o.scans) < log.scans.size()) log.scans.resize(o.scans);
  if (log.scans.size() < 2) throw std::invalid_argument(o.log + ": fewer than two laser scans");
  std::vector<Pose2> truth;
  for (const nav::CarmenScan& s : log.scans) truth.push_back(s.pose);
  const std::vector<Pose2> odometry = tools::MakeOdometry(truth, tools::OdometryNoise{}.Scaled(o.odom_noise), o.seed);
  const double duration_s = log.scans.back().timestamp_s - log.scans.front().timestamp_s;

  nlohmann::json result{{"mode", o.localize ? "localize" : "slam"},
                        {"log", o.log},
                        {"scans", log.scans.size()},
                        {"duration_s", duration_s},
                        {"seed", o.seed},
                        {"odom_noise", o.odom_noise}};
  std::vector<Pose2> estimate;
  std::vector<std::string> lines;
  double wall_s = 0.0;
  if (!o.localize) {
    nav::GraphSlam slam;
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < log.scans.size(); ++i) slam.AddScan(ToScan(log.scans[i], o.max_range_m), odometry[i]);
    slam.Finish();
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    estimate = slam.Trajectory();
    const nav::RelativeError local = nav::LocalRelativeError(truth, estimate);
    const nav::RelativeError revisit = nav::RevisitRelativeError(truth, estimate);
    const nav::RelativeError odom_local = nav::LocalRelativeError(truth, odometry);
    const nav::RelativeError odom_revisit = nav::RevisitRelativeError(truth, odometry);
    const nav::GraphSlamStats& st = slam.stats();
    result["local"] = ToJson(local);
    result["revisit"] = ToJson(revisit);
    result["odometry"] = {{"local", ToJson(odom_local)}, {"revisit", ToJson(odom_revisit)}};
    result["graph"] = {{"inserted", st.inserted},
                       {"submaps", st.submaps},
                       {"loop_searches", st.loop_searches},
                       {"loop_closures", st.loop_closures},
                       {"optimizations", st.optimizations}};
    lines = {Row("local", local), Row("revisit", revisit), Row("odometry local", odom_local),
             Row("odometry revisit", odom_revisit),
             "  graph: " + std::to_string(st.submaps) + " submaps, " + std::to_string(st.loop_closures) +
                 " loop closures of " + std::to_string(st.loop_searches) + " searches, " +
                 std::to_string(st.optimizations) + " optimizations"};
    if (o.reference_noise) {
      const tools::HatSigmas s = ConsecutiveHeadingNoise(log, truth, estimate, odometry, o.max_range_m);
      result["reference_noise"] = {
          {"consecutive_pairs", s.count}, {"corrected_poses_deg", s.a}, {"slam_deg", s.b}, {"scan_to_scan_deg", s.c}};
      char line[200];
      std::snprintf(line, sizeof line,
                    "  heading change between consecutive scans, own noise: corrected poses <= %.3f deg, SLAM %.3f, "
                    "scan to scan %.3f",
                    s.a, s.b, s.c);
      lines.push_back(line);
    }
    if (!o.png.empty()) WritePng(o.png, slam.RenderMap(0.05));
  } else {
    const nav::OccupancyGrid map = ReferenceMap(log, truth, o.max_range_m);
    if (!o.png.empty()) WritePng(o.png, map);
    nav::MonteCarloOptions mcl;
    mcl.max_range_m = o.max_range_m;
    nav::MonteCarloLocalization localization(map, mcl, o.seed);
    // The odometry's frame is anchored at the first true pose; the filter only sees its increments.
    const auto start = std::chrono::steady_clock::now();
    std::optional<std::size_t> relocalized;
    if (!o.global) localization.SetPose(truth.front(), 0.05, 0.02);
    for (std::size_t i = 0; i < log.scans.size(); ++i) {
      const nav::RangeScan scan = ToScan(log.scans[i], o.max_range_m);
      if (o.global && !relocalized) {
        if (localization.Relocalize(scan)) relocalized = i;
      }
      estimate.push_back(localization.Update(odometry[i], scan).pose);
    }
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Converged: at the first scan from which ten in a row are within 0.2 m and 5 degrees of the truth.
    const auto within = [&](std::size_t i) {
      const Pose2 e = truth[i].Inverse() * estimate[i];
      return e.translation().norm() <= 0.2 && std::abs(e.yaw_rad) <= 5.0 * std::numbers::pi / 180.0;
    };
    std::size_t converged = estimate.size();
    for (std::size_t i = 0, run = 0; i < estimate.size(); ++i) {
      run = within(i) ? run + 1 : 0;
      if (run == 10 || (run > 0 && i + 1 == estimate.size())) {
        converged = i + 1 - run;
        break;
      }
    }
    long outside = 0;
    for (std::size_t i = converged; i < estimate.size(); ++i) outside += !within(i);
    const std::vector<Pose2> t(truth.begin() + static_cast<long>(std::min(converged, truth.size())), truth.end());
    const std::vector<Pose2> e(estimate.begin() + static_cast<long>(std::min(converged, estimate.size())),
                               estimate.end());
    const nav::RelativeError error = nav::AbsoluteError(t, e);
    const nav::RelativeError odom_error = nav::AbsoluteError(truth, odometry);
    const bool did_converge = converged < estimate.size();
    const double converged_s = did_converge ? log.scans[converged].timestamp_s - log.scans.front().timestamp_s : 0.0;
    result["error"] = {{"rmse_translation_m", error.translation_m.rmse},
                       {"rmse_rotation_deg", error.rotation_deg.rmse},
                       {"max_translation_m", error.translation_m.max},
                       {"max_rotation_deg", error.rotation_deg.max},
                       {"converged_s", did_converge ? nlohmann::json(converged_s) : nlohmann::json(nullptr)},
                       {"converged_scan", did_converge ? nlohmann::json(converged) : nlohmann::json(nullptr)},
                       {"scans_off_after_converged", outside}};
    result["odometry"] = {{"rmse_translation_m", odom_error.translation_m.rmse},
                          {"rmse_rotation_deg", odom_error.rotation_deg.rmse}};
    char line[240];
    std::snprintf(line, sizeof line,
                  "  error (from scan %zu, %.1f s): rmse %.4f m, %.3f deg; max %.3f m, %.2f deg; %ld scans off after",
                  converged, converged_s, error.translation_m.rmse, error.rotation_deg.rmse, error.translation_m.max,
                  error.rotation_deg.max, outside);
    lines = {line};
    std::snprintf(line, sizeof line, "  odometry alone: rmse %.3f m, %.2f deg", odom_error.translation_m.rmse,
                  odom_error.rotation_deg.rmse);
    lines.push_back(line);
  }
  result["wall_s"] = wall_s;
  result["speed_x_realtime"] =
      duration_s > 0.0 && wall_s > 0.0 ? nlohmann::json(duration_s / wall_s) : nlohmann::json(nullptr);
  if (!o.trajectory.empty()) WriteTrajectory(o.trajectory, log, estimate);
  if (o.json) {
    std::cout << result.dump(2) << "\n";
  } else {
    std::printf("%s: %zu scans, %.0f s of log, %s in %.2f s (%s)\n", o.log.c_str(), log.scans.size(), duration_s,
                o.localize ? "localization" : "SLAM", wall_s,
                duration_s > 0.0 ? (std::to_string(duration_s / wall_s) + "x real time").c_str() : "no timestamps");
    for (const std::string& l : lines) std::printf("%s\n", l.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(ParseOptions(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corridor-slam-eval: %s\n", e.what());
    return 2;
  }
}
