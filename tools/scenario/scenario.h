// The scenario runner's core: the DPoom evaluation protocol (Kim et al., IEEE Access 2022, section IV, Tables 3 and
// 4) driven through the daemon's own node graph (server/app/graph.h) in lockstep with the simulator, faster than real
// time. There is no second wiring of the navigation here: the runner sets up the world, the people and the goal,
// configures the graph as a DPoom-like robot, posts the mission through the API as a building system would, steps the
// graph, and reads the outcome from the simulator and the per-frame work from the nodes' loop counters.
//
// A scenario is a world (a generated room, or any map or world file), a start and a goal 7 to 11 m apart, static
// obstacles the robot's map does not show and pedestrians, all drawn from one seed. The pedestrians follow the paper's
// protocol (CrowdKind::kPaper, the default) or a harder one of our own (kPacing); see CrowdKind.
// The robot (0.26 m/s, a depth camera of 85.2 x 58 degrees at 18 Hz) follows a global path planned on its map, with
// the local policy the graph is configured with (mission.policy):
//   - morp-rb: MORP lanes and corridor's local navigator;
//   - voxel-reactive: the comparison pipeline, a point cloud downsampled in a voxel grid with obstacle extraction,
//     feeding a simple reactive controller;
//   - morp-il: morp-rb with MORP-IL's network in MORP-RB's place (nav/policy/morp_il.h);
//   - takiguchi: morp-rb with Takiguchi's direction network in MORP-RB's place (nav/policy/takiguchi.h).
// A run succeeds when the robot is within goal_tolerance_m of the goal, fails with a collision when its footprint
// touches anything (wall, obstacle, person), and times out otherwise. People do not see the robot, so many contacts
// are a person walking into it from its side or back; each collision also says whether the robot drove into it (it
// was closing in faster than the person), and the tables count those separately. The robot's pose is the simulator's
// ground truth (localization.source: sim_truth): the scenarios measure local navigation, as the paper's do. With
// `laser`, the robot also carries corridor's optional 2D laser and the graph tracks moving objects all round it;
// without, it tracks them in the depth camera's view (`camera_tracking`, the daemon's default; off: MORP-RB alone,
// DPoom's robot as published); the voxel-reactive baseline does neither.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drivers/sim/crowd.h"
#include "drivers/sim/sensors.h"
#include "drivers/sim/world.h"
#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"
#include "nav/policy/demonstrations.h"
#include "nav/policy/local_policy.h"
#include "nav/policy/morp_il.h"
#include "nav/policy/takiguchi.h"

namespace corridor::scenario {

// The local policy the daemon's graph is configured with (mission.policy).
using Policy = nav::LocalPolicyKind;
using nav::ToString;
inline std::optional<Policy> ParsePolicy(const std::string& name) { return nav::ParseLocalPolicy(name); }

// How the pedestrians walk. Neither kind sees the robot; both avoid each other and the obstacles with ORCA.
enum class CrowdKind {
  // The paper's, as DPoom's authors set up their Gazebo evaluation (github.com/SeunghyunLim/Dpoom_gazebo: five
  // agents placed in the area the robot must cross, each driven once to its own target a few metres away at about
  // 0.35 m/s, then stopped): people start 3 to 7 m before the robot's goal within 2.5 m of the straight way, walk
  // once 2.5 to 5 m at up to 0.35 m/s, and stand at the end of their walk for the rest of the run.
  kPaper,
  // Ours, harder: people on routes 4 to 10 m long anywhere in the world, walking them back and forth at 0.8 m/s
  // (three times the robot's speed) for the whole run, reaching the robot from any side.
  kPacing,
};
const char* ToString(CrowdKind kind);
std::optional<CrowdKind> ParseCrowdKind(const std::string& name);

// Where the runs are: ASNS's three settings (the paper's dimensions are not in the tree; these are corridor's).
enum class SettingKind {
  kRoom,      // rooms of 12 to 15 m a side (DPoom's evaluation, and the default)
  kCorridor,  // a corridor 2.4 to 3 m wide and 16 to 20 m long
  kOpen,      // an open hall of 25 to 30 m a side
};
const char* ToString(SettingKind kind);
std::optional<SettingKind> ParseSettingKind(const std::string& name);

// The static obstacles' size: DPoom's, or ASNS's low, medium and large ones (cylinders and boxes alike).
enum class ObstacleSize {
  kDpoom,   // 1 m across, 1 m high (the default)
  kLow,     // 0.3 m across, 0.15 m high: under a laser, over what the robot drives over
  kMedium,  // 0.5 m across, 0.5 m high
  kLarge,   // 1.2 m across, 1.2 m high
};
const char* ToString(ObstacleSize size);
std::optional<ObstacleSize> ParseObstacleSize(const std::string& name);

struct ScenarioOptions {
  std::filesystem::path world;  // a .yaml map or a mesh world; empty: generated rooms of 12 to 15 m
  int worlds = 10;
  int runs = 3;  // per world
  std::uint32_t seed = 1;
  int pedestrians = 0;  // 0 to 5 in the paper's protocol
  CrowdKind crowd = CrowdKind::kPaper;
  int static_obstacles = 0;  // 0 to 9: cubes and cylinders of obstacle_size
  SettingKind setting = SettingKind::kRoom;
  ObstacleSize obstacle_size = ObstacleSize::kDpoom;
  double min_goal_m = 7.0;
  double max_goal_m = 11.0;
  double goal_tolerance_m = 0.25;
  // A run succeeds when the mission says it arrived (the pose controller's last centimetres, mission.*_tolerance)
  // instead of within goal_tolerance_m, and its final error is measured: ASNS's Table 8.
  bool until_arrived = false;
  double max_speed_mps = 0.26;   // DPoom's
  double camera_rate_hz = 18.0;  // DPoom's control rate
  double timeout_s = 0.0;        // 0: three times the straight-line time, plus 20 s
  std::vector<Policy> policies = {Policy::kMorpRb, Policy::kVoxelReactive};
  // corridor's optional 2D laser (360 beams, 10 Hz) on the robot: morp-rb then tracks moving objects around it
  // and steps out of their way. Off: DPoom's camera only.
  bool laser = false;
  // Without the laser, morp-rb tracks people in the depth camera's view instead (nav/ground/depth_scan.h) and
  // evades them, never backing, as the daemon does by default (tracking.camera). Off: DPoom's robot as published.
  bool camera_tracking = true;
  // The camera is a stereo pair (the simulator's, drivers/sim/sim_stereo.h: two textured views 12 cm apart, matched
  // by the depth path a real stereo camera's frames take) instead of a depth sensor.
  bool stereo = false;
  // With stereo: ASNS's camera of three views (12 and 24 cm: drivers/stereo/multi_baseline.h) and the multi-view
  // filter over posed frames (nav/ground/multi_view.h), its MMSVF.
  bool mmsvf = false;
  // The camera rides the simulator's pan servo and the gaze turns it (ASNS's IGM, nav/policy/gaze.h).
  bool pan = false;
  // The depth path's ground test is ASNS's floor detection (nav/ground/afds.h) instead of MORP's.
  bool afds = false;
  // People see the robot and keep clear of it (drivers::sim::CrowdOptions::see_robot); off: they ignore it, as in the
  // DPoom evaluation.
  bool people_see_robot = false;
  bool trace = false;  // every morp-rb decision and every collision's surroundings on stderr
  // Only this world and run (indices from 0), to look into one with `trace`; the same layout as in the full set.
  std::optional<std::pair<int, int>> only;
  // morp-il's and takiguchi's networks (each required with its policy; takiguchi's not while it teaches: its
  // expert drives).
  std::shared_ptr<const nav::Mlp> morp_il;
  std::shared_ptr<const nav::Mlp> takiguchi;
  // Takiguchi's rays (the network's inputs): how many, over how wide a field centred ahead (360: all round).
  int takiguchi_rays = 91;
  double takiguchi_field_deg = 180.0;
  // Training only (corridor-train): every run of morp-rb or morp-il records its steps' inputs and the rules' commands
  // here, and mixes who drives (nav::Demonstrations).
  std::shared_ptr<nav::Demonstrations> teach;
  // With `teach`: Takiguchi's expert labels from the simulator's people rather than the tracker's (Demonstrations).
  bool privileged = false;
};

// Takiguchi's options as the runs configure the navigator (rays, field, the robot's speed).
nav::TakiguchiOptions DirectionOptions(const ScenarioOptions& options);

// Whether the point p is in the view of `camera` on the robot at `pose`, by the simulator's truth: within its
// horizontal field and range, no wall of `grid` in between (sampled every half cell). People do not hide one another
// here, so this errs towards seen.
bool InCameraView(const nav::OccupancyGrid& grid, const drivers::sim::SimCameraOptions& camera, const nav::Pose2& pose,
                  const Eigen::Vector2d& p);

// Everything one run needs, drawn from the seed.
struct Layout {
  int world_index = 0;
  int run_index = 0;
  std::uint32_t seed = 0;
  drivers::sim::World world;  // with the static obstacles
  nav::OccupancyGrid map;     // what the robot knows: no obstacles, no people
  nav::Pose2 start;
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  std::vector<drivers::sim::PedestrianRoute> routes;
  drivers::sim::CrowdOptions crowd;  // how they walk
};

// Throws std::runtime_error when the world has no room for the protocol (no start and goal 7-11 m apart).
Layout MakeLayout(const ScenarioOptions& options, int world_index, int run_index);

enum class Outcome { kSuccess, kCollision, kTimeout, kNoPath };
const char* ToString(Outcome outcome);

struct RunResult {
  Policy policy = Policy::kMorpRb;
  int world_index = 0;
  int run_index = 0;
  std::uint32_t seed = 0;
  Outcome outcome = Outcome::kTimeout;
  double time_s = 0.0;         // simulated, to the end of the run
  double path_length_m = 0.0;  // driven
  // The smallest gap between the robot's footprint and a person's over the run (negative: they overlapped); infinity
  // without people.
  double closest_person_m = std::numeric_limits<double>::infinity();
  std::string collided_with;         // "wall or obstacle", "person"
  bool robot_drove_into_it = false;  // a collision the robot closed in on (always, for walls and obstacles)
  // A collision with a person: how long before it they were last in the camera's view (its field and range, no wall
  // between, by the simulator's truth; 0: in view then), nullopt when never since the start: no camera could have
  // shown them to the robot.
  std::optional<double> person_in_view_s;
  // until_arrived: how far from the goal the robot stands when its mission says it arrived, by the simulator's truth.
  std::optional<double> final_error_m;
  // Wall time per depth frame from the nodes' loop counters: the ground node's front end (MORP and the depth scan, or
  // cloud + voxel grid + extraction) and the mission node's frame (the local policy, and publishing its step).
  std::vector<double> depth_ms;
  std::vector<double> policy_ms;
  std::vector<double> tracking_ms;  // per laser scan, or depth frame with camera_tracking: the tracking node's
};

// One run of `policy` in `layout`. Deterministic for a layout and policy (timings aside).
RunResult RunOnce(const Layout& layout, Policy policy, const ScenarioOptions& options);

struct PolicySummary {
  Policy policy = Policy::kMorpRb;
  int runs = 0;
  double success = 0.0;  // fractions of runs
  double collision = 0.0;
  double robot_collision = 0.0;  // collisions the robot drove into
  double timeout = 0.0;
  double mean_time_to_goal_s = 0.0;  // over successful runs
  double mean_path_length_m = 0.0;   // over successful runs
  // The closest a person came over the runs with people: the mean of each run's closest gap, and the smallest
  // (nullopt without people).
  std::optional<double> mean_closest_person_m;
  std::optional<double> min_closest_person_m;
  double depth_ms = 0.0;  // means over every frame of every run
  double policy_ms = 0.0;
  double total_ms = 0.0;
  double total_p99_ms = 0.0;
  std::uint64_t frames = 0;
  double tracking_ms = 0.0;  // mean per laser scan (or depth frame); 0 without tracking
  std::uint64_t scans = 0;
  // until_arrived: the final errors of the runs that arrived, their mean and largest.
  std::optional<double> mean_final_error_m;
  std::optional<double> max_final_error_m;
};

// Every world x run x policy. `progress` (optional) gets each result as it is done.
std::vector<RunResult> RunAll(const ScenarioOptions& options,
                              const std::function<void(const RunResult&)>& progress = nullptr);
std::vector<PolicySummary> Summarise(const std::vector<RunResult>& results);

}  // namespace corridor::scenario
