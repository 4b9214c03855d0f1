// corridor-scenario: the DPoom evaluation (Tables 3 and 4) on the simulator, in lockstep faster than real time.
// See tools/scenario/scenario.h for the protocol and docs/benchmarks.md for results.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "tools/common/command_line.h"
#include "tools/scenario/scenario.h"

namespace {

using corridor::scenario::Policy;
using corridor::scenario::ScenarioOptions;

constexpr const char* kUsage = R"(usage: corridor-scenario [options]

Runs the DPoom evaluation protocol: a DPoom-like robot (0.26 m/s, camera 85.2 x 58 degrees) drives to a goal 7 to
11 m away among pedestrians and unmapped static obstacles, with each local policy, and prints the paper's Table 4
(success, collision, time to goal) and Table 3 (milliseconds per depth frame).

  --world FILE        a map (.yaml) or world (.world, .sdf, mesh) to run in; default: generated rooms of 12-15 m
  --worlds N          worlds (layouts) to run, default 10
  --runs N            runs per world, default 3
  --seed N            default 1; the same seed gives the same scenarios
  --only W/R          only world W's run R (from 0; within --worlds and --runs), e.g. to --trace it
  --pedestrians N     0 to 5, default 0
  --crowd KIND        how they walk: paper (default: placed in the robot's way, each walks once 2.5-5 m at 0.35 m/s
                      and stands, as in DPoom's evaluation) or pacing (harder: routes anywhere, walked back and
                      forth at 0.8 m/s for the whole run)
  --static N          static obstacles, 0 to 9, default 0
  --obstacle-size S   dpoom (default: 1 m across and high), or ASNS's low (0.3 m across, 0.15 m high), medium (0.5,
                      0.5) or large (1.2, 1.2)
  --setting KIND      room (default: rooms of 12-15 m), or ASNS's corridor (2.4-3 m wide, 16-20 m long) or open (a
                      hall of 25-30 m)
  --policy NAME       morp-rb, voxel-reactive, morp-il, takiguchi or flmc (ASNS's fuzzy controllers); repeat for
                      several; default the first two
  --weights FILE      morp-il's network, default config/policies/morp_il.weights
  --takiguchi-weights FILE
                      takiguchi's network, default config/policies/takiguchi.weights
  --takiguchi-rays N  its rays, default 91 (the paper's)
  --takiguchi-field DEG
                      over how wide a field, centred ahead, default 180 (the paper's); 360: all round
  --laser             give the robot corridor's optional 2D laser: morp-rb tracks moving objects and evades them
  --no-camera-tracking
                      without the laser, morp-rb does not track people in the depth camera's view (DPoom's robot as
                      published); by default it tracks and evades them, as the daemon does
  --camera KIND       depth (default: a depth sensor, a RealSense's model), stereo (two textured views 12 cm apart
                      matched into depth, as a stereo camera's frames are) or mmsvf (ASNS's: three views, 12 and
                      24 cm, fused, and filtered over posed frames)
  --pan               the camera rides a pan servo (the simulator's) and the gaze turns it (ASNS's IGM)
  --until-arrived     a run succeeds when its mission says it arrived (not within 0.25 m), and the final error is
                      measured (ASNS's Table 8)
  --ground TEST       morp (default: MORP's ground segmentation) or afds (ASNS's floor detection) gives the lanes
  --people-see-robot  the people keep clear of the robot too (default: they walk as if it were not there, as in
                      DPoom's evaluation)
  --timeout S         per run, default 3 x straight-line time + 20 s
  --json              machine-readable results (every run and the summaries) on stdout
  --trace             every morp-rb decision (pose, mode, lanes) and each collision's surroundings on stderr
  --quiet             no progress on stderr
  --help
)";

int ParseInt(const std::string& flag, const std::string& text, int lo, int hi) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < lo || value > hi) {
    throw std::invalid_argument(flag + ": expected an integer from " + std::to_string(lo) + " to " +
                                std::to_string(hi) + ", got '" + text + "'");
  }
  return value;
}

nlohmann::json OrNull(const std::optional<double>& value) { return value ? nlohmann::json(*value) : nullptr; }

nlohmann::json ToJson(const corridor::scenario::PolicySummary& s) {
  return {{"policy", ToString(s.policy)},
          {"runs", s.runs},
          {"success", s.success},
          {"collision", s.collision},
          {"robot_collision", s.robot_collision},
          {"timeout", s.timeout},
          {"mean_time_to_goal_s", s.mean_time_to_goal_s},
          {"mean_path_length_m", s.mean_path_length_m},
          {"mean_closest_person_m", OrNull(s.mean_closest_person_m)},
          {"min_closest_person_m", OrNull(s.min_closest_person_m)},
          {"depth_ms", s.depth_ms},
          {"policy_ms", s.policy_ms},
          {"total_ms", s.total_ms},
          {"total_p99_ms", s.total_p99_ms},
          {"frames", s.frames},
          {"tracking_ms", s.tracking_ms},
          {"scans", s.scans}};
}

// The --camera a run used, as the flag names it.
const char* CameraName(const ScenarioOptions& options) {
  if (!options.stereo) return "depth";
  return options.mmsvf ? "mmsvf" : "stereo";
}

}  // namespace

// A policy's network from `file`, checked by `check`; MlpFormatError naming the flag and file when it cannot drive.
std::shared_ptr<const corridor::nav::Mlp> LoadNetwork(const std::string& flag, const std::filesystem::path& file,
                                                      const std::function<void(const corridor::nav::Mlp&)>& check) {
  try {
    auto net = std::make_shared<corridor::nav::Mlp>(corridor::nav::Mlp::Load(file));
    check(*net);
    return net;
  } catch (const std::exception& e) {
    throw corridor::nav::MlpFormatError(flag + " " + file.string() + ": " + e.what());
  }
}

int main(int argc, char** argv) {
  // The graph of each run logs as corridord does; only what goes wrong matters here.
  spdlog::set_level(spdlog::level::warn);
  ScenarioOptions options;
  bool json = false;
  bool quiet = false;
  std::filesystem::path weights = "config/policies/morp_il.weights";
  std::filesystem::path direction_weights = "config/policies/takiguchi.weights";
  try {
    std::vector<Policy> policies;
    for (corridor::tools::Arguments args(argc, argv, 1); args.Next();) {
      const std::string flag = args.current();
      const auto value = [&] { return args.Value(); };
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--world") {
        options.world = value();
      } else if (flag == "--worlds") {
        options.worlds = ParseInt(flag, value(), 1, 1000);
      } else if (flag == "--runs") {
        options.runs = ParseInt(flag, value(), 1, 1000);
      } else if (flag == "--seed") {
        options.seed = static_cast<std::uint32_t>(ParseInt(flag, value(), 0, 1 << 30));
      } else if (flag == "--only") {
        const std::string text = value();
        const auto slash = text.find('/');
        if (slash == std::string::npos) throw std::invalid_argument("--only: expected W/R, got '" + text + "'");
        options.only = {ParseInt(flag, text.substr(0, slash), 0, 999), ParseInt(flag, text.substr(slash + 1), 0, 999)};
      } else if (flag == "--pedestrians") {
        options.pedestrians = ParseInt(flag, value(), 0, 20);
      } else if (flag == "--crowd") {
        const std::string name = value();
        const auto kind = corridor::scenario::ParseCrowdKind(name);
        if (!kind) throw std::invalid_argument("--crowd: unknown kind '" + name + "' (paper, pacing)");
        options.crowd = *kind;
      } else if (flag == "--setting") {
        const std::string name = value();
        const auto kind = corridor::scenario::ParseSettingKind(name);
        if (!kind) throw std::invalid_argument("--setting: unknown setting '" + name + "' (room, corridor, open)");
        options.setting = *kind;
      } else if (flag == "--obstacle-size") {
        const std::string name = value();
        const auto size = corridor::scenario::ParseObstacleSize(name);
        if (!size) {
          throw std::invalid_argument("--obstacle-size: unknown size '" + name + "' (dpoom, low, medium, large)");
        }
        options.obstacle_size = *size;
      } else if (flag == "--static") {
        options.static_obstacles = ParseInt(flag, value(), 0, 30);
      } else if (flag == "--policy") {
        const std::string name = value();
        const auto policy = corridor::scenario::ParsePolicy(name);
        if (!policy) {
          throw std::invalid_argument("--policy: unknown policy '" + name +
                                      "' (morp-rb, voxel-reactive, morp-il, takiguchi, flmc)");
        }
        policies.push_back(*policy);
      } else if (flag == "--weights") {
        weights = value();
      } else if (flag == "--takiguchi-weights") {
        direction_weights = value();
      } else if (flag == "--takiguchi-rays") {
        options.takiguchi_rays = ParseInt(flag, value(), 3, 10000);
      } else if (flag == "--takiguchi-field") {
        options.takiguchi_field_deg = ParseInt(flag, value(), 1, 360);
      } else if (flag == "--timeout") {
        options.timeout_s = ParseInt(flag, value(), 1, 100000);
      } else if (flag == "--laser") {
        options.laser = true;
      } else if (flag == "--camera-tracking") {
        options.camera_tracking = true;  // the default; kept for older commands
      } else if (flag == "--no-camera-tracking") {
        options.camera_tracking = false;
      } else if (flag == "--camera") {
        const std::string kind = value();
        if (kind != "depth" && kind != "stereo" && kind != "mmsvf") {
          throw std::invalid_argument("--camera: depth, stereo or mmsvf, got '" + kind + "'");
        }
        options.stereo = kind != "depth";
        options.mmsvf = kind == "mmsvf";
      } else if (flag == "--pan") {
        options.pan = true;
      } else if (flag == "--until-arrived") {
        options.until_arrived = true;
      } else if (flag == "--ground") {
        const std::string test = value();
        if (test != "morp" && test != "afds") throw std::invalid_argument("--ground: morp or afds, got '" + test + "'");
        options.afds = test == "afds";
      } else if (flag == "--people-see-robot") {
        options.people_see_robot = true;
      } else if (flag == "--json") {
        json = true;
      } else if (flag == "--trace") {
        options.trace = true;
      } else if (flag == "--quiet") {
        quiet = true;
      } else {
        throw std::invalid_argument("unknown option '" + flag + "'");
      }
    }
    if (!policies.empty()) options.policies = policies;
    const auto uses = [&](Policy p) {
      return std::find(options.policies.begin(), options.policies.end(), p) != options.policies.end();
    };
    if (uses(Policy::kMorpIl)) {
      options.morp_il = LoadNetwork("--weights", weights, [](const corridor::nav::Mlp& net) {
        corridor::nav::CheckMorpIlNetwork(net, corridor::nav::MorpIlOptions{});
      });
    }
    if (uses(Policy::kTakiguchi)) {
      options.takiguchi = LoadNetwork("--takiguchi-weights", direction_weights, [&](const corridor::nav::Mlp& net) {
        corridor::nav::CheckTakiguchiNetwork(net, corridor::scenario::DirectionOptions(options));
      });
    }
  } catch (const corridor::nav::MlpFormatError& e) {
    std::cerr << "corridor-scenario: " << e.what() << '\n';
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "corridor-scenario: " << e.what() << "\n\n" << kUsage;
    return 2;
  }

  std::vector<corridor::scenario::RunResult> results;
  try {
    results = corridor::scenario::RunAll(options, [&](const corridor::scenario::RunResult& r) {
      if (quiet) return;
      char seen[64] = "";
      if (r.collided_with == "person" && r.person_in_view_s) {
        std::snprintf(seen, sizeof seen, ", last in the camera's view %.1f s before", *r.person_in_view_s);
      } else if (r.collided_with == "person") {
        std::snprintf(seen, sizeof seen, ", never in the camera's view");
      }
      std::fprintf(
          stderr, "world %d run %d %-15s %-9s %6.1f s%s%s%s%s\n", r.world_index, r.run_index, ToString(r.policy),
          ToString(r.outcome), r.time_s, r.collided_with.empty() ? "" : " with ", r.collided_with.c_str(),
          r.outcome == corridor::scenario::Outcome::kCollision && !r.robot_drove_into_it ? " (walked into the robot)"
                                                                                         : "",
          seen);
    });
  } catch (const std::exception& e) {
    std::cerr << "corridor-scenario: " << e.what() << "\n";
    return 1;
  }
  const auto summaries = corridor::scenario::Summarise(results);

  if (json) {
    nlohmann::json doc;
    doc["options"] = {{"world", options.world.empty() ? "generated rooms" : options.world.string()},
                      {"worlds", options.worlds},
                      {"runs", options.runs},
                      {"seed", options.seed},
                      {"pedestrians", options.pedestrians},
                      {"crowd", ToString(options.crowd)},
                      {"static", options.static_obstacles},
                      {"setting", ToString(options.setting)},
                      {"obstacle_size", ToString(options.obstacle_size)},
                      {"laser", options.laser},
                      {"camera", CameraName(options)},
                      {"pan", options.pan},
                      {"ground", options.afds ? "afds" : "morp"},
                      {"until_arrived", options.until_arrived},
                      {"camera_tracking", options.camera_tracking},
                      {"people_see_robot", options.people_see_robot},
                      {"max_speed_mps", options.max_speed_mps},
                      {"camera_rate_hz", options.camera_rate_hz}};
    for (const auto& r : results) {
      nlohmann::json run = {{"policy", ToString(r.policy)},
                            {"world", r.world_index},
                            {"run", r.run_index},
                            {"seed", r.seed},
                            {"outcome", ToString(r.outcome)},
                            {"time_s", r.time_s},
                            {"path_length_m", r.path_length_m},
                            {"closest_person_m", std::isfinite(r.closest_person_m) ? nlohmann::json(r.closest_person_m)
                                                                                   : nlohmann::json(nullptr)},
                            {"collided_with", r.collided_with},
                            {"robot_drove_into_it", r.robot_drove_into_it}};
      if (r.final_error_m) run["final_error_m"] = *r.final_error_m;
      // A person's collision: seconds since they were last in the camera's view, null for never.
      if (r.collided_with == "person") {
        run["person_in_view_s"] = OrNull(r.person_in_view_s);
      }
      doc["runs"].push_back(std::move(run));
    }
    for (const auto& s : summaries) doc["summary"].push_back(ToJson(s));
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  const std::string where =
      options.world.empty() ? std::string("generated ") + ToString(options.setting) + "s" : options.world.string();
  std::printf("%d worlds x %d runs, %d pedestrians (%s), %d static obstacles (%s), seed %u, %s, %s, %s camera%s%s\n\n",
              options.worlds, options.runs, options.pedestrians, ToString(options.crowd), options.static_obstacles,
              ToString(options.obstacle_size), options.seed, where.c_str(),
              options.laser             ? "camera and laser"
              : options.camera_tracking ? "camera only, tracking people in its view"
                                        : "camera only, no tracking",
              CameraName(options), options.pan ? " on a pan servo (gaze)" : "", options.afds ? ", AFDS" : "");
  std::printf(
      "Table 4: outcomes (robot-caused: collisions the robot drove into, not people walking into it)\n"
      "%-16s %5s %8s %10s %14s %8s %18s %10s %18s\n",
      "policy", "runs", "success", "collision", "robot-caused", "timeout", "time to goal (s)", "path (m)",
      "closest person (m)");
  for (const auto& s : summaries) {
    char closest[32] = "-";  // no people
    if (s.mean_closest_person_m) std::snprintf(closest, sizeof closest, "%.2f", *s.mean_closest_person_m);
    std::printf("%-16s %5d %8.2f %10.2f %14.2f %8.2f %18.1f %10.2f %18s\n", ToString(s.policy), s.runs, s.success,
                s.collision, s.robot_collision, s.timeout, s.mean_time_to_goal_s, s.mean_path_length_m, closest);
  }
  std::printf("\nTable 3: milliseconds per depth frame (this machine, one core)\n%-16s %17s %10s %10s %10s %8s\n",
              "policy", "depth processing", "policy", "total", "total p99", "frames");
  for (const auto& s : summaries) {
    std::printf("%-16s %17.3f %10.4f %10.3f %10.3f %8llu\n", ToString(s.policy), s.depth_ms, s.policy_ms, s.total_ms,
                s.total_p99_ms, static_cast<unsigned long long>(s.frames));
  }
  for (const auto& s : summaries) {
    if (!s.mean_final_error_m) continue;
    std::printf("\n%s: final error when its mission arrived (Table 8): mean %.1f cm, largest %.1f cm\n",
                ToString(s.policy), 100.0 * *s.mean_final_error_m, 100.0 * *s.max_final_error_m);
  }
  for (const auto& s : summaries) {
    if (s.scans == 0) continue;
    std::printf("\n%s: moving-object tracking %.3f ms per scan (%llu scans: laser, or depth frames)\n",
                ToString(s.policy), s.tracking_ms, static_cast<unsigned long long>(s.scans));
  }
  return 0;
}
