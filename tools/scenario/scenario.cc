#include "tools/scenario/scenario.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>

#include <stdlib.h>

#include <nlohmann/json.hpp>

#include "drivers/sim/sim_robot.h"
#include "nav/geometry/sensor_view.h"
#include "nav/planner/planner.h"
#include "server/app/graph.h"
#include "server/runtime/topics.h"

namespace corridor::scenario {
namespace {

namespace fs = std::filesystem;
using drivers::sim::PedestrianRoute;
using drivers::sim::StaticObstacle;
using drivers::sim::World;
using server::Bus;

constexpr double kRobotRadiusM = 0.2;
constexpr double kPersonRadiusM = 0.25;
constexpr double kRoomResolutionM = 0.05;

std::mt19937 Rng(std::uint32_t seed, int world_index, int run_index) {
  std::seed_seq seq{seed, static_cast<std::uint32_t>(world_index), static_cast<std::uint32_t>(run_index)};
  return std::mt19937(seq);
}

// True when a disc of `radius` at p is inside the grid and clear of occupied and unknown cells.
bool Clear(const nav::OccupancyGrid& grid, const Eigen::Vector2d& p, double radius) {
  const auto centre = grid.WorldToCell(p);
  if (!centre) return false;
  const int reach = static_cast<int>(std::ceil(radius / grid.resolution_m()));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const nav::CellIndex c{centre->x + dx, centre->y + dy};
      if (!grid.Contains(c)) return false;
      if ((grid.CellCenter(c) - p).norm() > radius + grid.resolution_m()) continue;
      if (grid.at(c) < 0 || grid.at(c) >= nav::kOccupiedCell) return false;
    }
  }
  return true;
}

nav::Costmap RobotCostmap(const nav::OccupancyGrid& grid) {
  nav::CostmapOptions options;
  options.robot_radius_m = kRobotRadiusM;
  return nav::Costmap(grid, {}, options);
}

bool PathExists(const nav::Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  return nav::PlanPath(costmap, start, goal).ok();
}

// The world before obstacles, loaded or generated for world_index.
World BaseWorld(const ScenarioOptions& options, int world_index, nav::OccupancyGrid& map) {
  if (!options.world.empty()) {
    World world = drivers::sim::LoadWorld(options.world, drivers::sim::WorldOptions{});
    map = world.source_map ? *world.source_map : world.collision;
    return world;
  }
  std::mt19937 rng = Rng(options.seed, world_index, -1);
  const auto [lo, hi] = options.setting == SettingKind::kOpen ? std::pair{25.0, 30.0} : std::pair{12.0, 15.0};
  std::uniform_real_distribution<double> size(lo, hi);
  double width = size(rng);
  double height = size(rng);
  if (options.setting == SettingKind::kCorridor) {
    width = std::uniform_real_distribution<double>(16.0, 20.0)(rng);
    height = std::uniform_real_distribution<double>(2.4, 3.0)(rng);
  }
  map = drivers::sim::RoomMap(width, height, kRoomResolutionM);
  return drivers::sim::WorldFromMap(map, drivers::sim::WorldOptions{});
}

// --trace output: one line per morp-rb decision, and what surrounded a collision.
void TraceDecision(double now_s, const nav::Pose2& pose, const nav::LocalStep& step,
                   const std::vector<nav::LaneResult>& lanes, const nav::Surroundings* around,
                   const std::vector<drivers::sim::Pedestrian>& people,
                   const std::vector<Eigen::Vector2d>& remembered) {
  std::fprintf(stderr, "t %.2f pose %.2f %.2f %.2f mode %s%s%s nearest %.2f twist %.2f %.2f lanes", now_s, pose.x_m,
               pose.y_m, pose.yaw_rad, nav::ToString(step.mode), step.guarded ? " guarded" : "",
               step.evading ? " evading" : "", step.nearest_m, step.twist.linear_mps, step.twist.angular_rps);
  for (const auto& l : lanes) std::fprintf(stderr, " %.2f%s", l.free_distance_m, l.dead_end ? "*" : "");
  if (around != nullptr) {
    std::fprintf(stderr, " movers");
    for (const auto& o : around->objects) {
      if (o.moving) {
        std::fprintf(stderr, " (%.2f %.2f v %.2f %.2f r %.2f%s)", o.position.x(), o.position.y(), o.velocity.x(),
                     o.velocity.y(), o.radius_m, o.seen ? "" : " unseen");
      }
    }
    std::fprintf(stderr, " standing");
    for (const auto& o : around->objects) {
      if (!o.moving) std::fprintf(stderr, " (%.2f %.2f r %.2f)", o.position.x(), o.position.y(), o.radius_m);
    }
  }
  std::fprintf(stderr, " people");  // the simulator's truth, to compare with what was tracked
  for (const auto& p : people) {
    std::fprintf(stderr, " (%.2f %.2f v %.2f %.2f)", p.position.x(), p.position.y(), p.velocity.x(), p.velocity.y());
  }
  std::fprintf(stderr, " remembered within 0.6 m (robot frame)");  // what the obstacle memory guards against
  for (const Eigen::Vector2d& p : remembered) {
    const Eigen::Vector2d local = pose.Inverse().Transform(p);
    if (local.norm() <= 0.6) std::fprintf(stderr, " (%.2f %.2f)", local.x(), local.y());
  }
  std::fprintf(stderr, "\n");
}

void TraceCollision(const Layout& layout, const nav::Pose2& pose, const std::vector<drivers::sim::Pedestrian>& people,
                    const std::vector<Eigen::Vector2d>& remembered) {
  std::fprintf(stderr, "collision at %.2f %.2f yaw %.2f; goal %.2f %.2f\n", pose.x_m, pose.y_m, pose.yaw_rad,
               layout.goal.x(), layout.goal.y());
  for (const auto& p : people) {
    const Eigen::Vector2d local = pose.Inverse().Transform(p.position);
    std::fprintf(stderr, "  person at %.2f %.2f (robot frame %.2f %.2f) moving %.2f %.2f\n", p.position.x(),
                 p.position.y(), local.x(), local.y(), p.velocity.x(), p.velocity.y());
  }
  for (const auto& o : layout.world.obstacles) {
    std::fprintf(stderr, "  obstacle %s at %.2f %.2f size %.2f, distance %.2f\n", ShapeName(o.shape), o.center.x(),
                 o.center.y(), o.size_m, (o.center - pose.translation()).norm());
  }
  // What the footprint touches of the world's walls and obstacles, and whether the robot's map has it.
  std::fprintf(stderr, "  touching (robot frame; M: on the robot's map):");
  const nav::OccupancyGrid& world = layout.world.collision;
  const double res = world.resolution_m();
  const auto centre = world.WorldToCell(pose.translation());
  const int reach = static_cast<int>(std::ceil((kRobotRadiusM + res) / res));
  for (int dy = -reach; centre && dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const nav::CellIndex c{centre->x + dx, centre->y + dy};
      if (!world.Contains(c) || world.at(c) < nav::kOccupiedCell) continue;
      const Eigen::Vector2d at = world.CellCenter(c);
      if ((at - pose.translation()).norm() > kRobotRadiusM + res) continue;
      const auto known = layout.map.WorldToCell(at);
      const bool mapped = known && layout.map.at(*known) >= nav::kOccupiedCell;
      const Eigen::Vector2d local = pose.Inverse().Transform(at);
      std::fprintf(stderr, " (%.2f %.2f%s)", local.x(), local.y(), mapped ? " M" : "");
    }
  }
  std::fprintf(stderr, "\n  remembered within 1 m (robot frame):");
  for (const Eigen::Vector2d& p : remembered) {
    const Eigen::Vector2d local = pose.Inverse().Transform(p);
    if (local.norm() <= 1.0) std::fprintf(stderr, " (%.2f %.2f)", local.x(), local.y());
  }
  std::fprintf(stderr, "\n");
}

// A temporary state directory for one run's graph (its database and maps), removed afterwards.
class StateDir {
 public:
  StateDir() {
    std::string pattern = (fs::temp_directory_path() / "corridor-scenario-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot make a temporary state directory");
    path_ = pattern;
  }
  StateDir(const StateDir&) = delete;
  StateDir& operator=(const StateDir&) = delete;
  ~StateDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

nav::TakiguchiOptions DirectionOptions(const ScenarioOptions& options) {
  nav::TakiguchiOptions direction;
  direction.rays = options.takiguchi_rays;
  direction.field_rad = options.takiguchi_field_deg * std::numbers::pi / 180.0;
  direction.max_linear_mps = options.max_speed_mps;
  return direction;
}

namespace {

// The daemon's configuration for a DPoom-like robot: 0.26 m/s, 0.2 m radius, the simulator's truth for its pose (the
// scenarios measure local navigation), the policy under test, tracking as the options say.
server::Config GraphConfig(const drivers::sim::SimOptions& sim, Policy policy, const ScenarioOptions& options,
                           const fs::path& state_dir) {
  server::Config config;
  config.store.state_dir = state_dir;
  config.sim.robot = sim;
  config.devices.laser.driver = sim.laser.enabled ? server::DeviceDriver::kSim : server::DeviceDriver::kNone;
  config.localization.source = server::LocalizationOptions::Source::kSimTruth;
  config.planner.robot_radius_m = kRobotRadiusM;
  config.safety.front_offset_m = kRobotRadiusM;
  config.mission.policy = policy;
  config.ground.test = options.afds ? server::GroundTest::kAfds : server::GroundTest::kMorp;
  config.multi_view.enabled = options.stereo && options.mmsvf;
  config.devices.camera.pan_driver = options.pan ? server::DeviceDriver::kSim : server::DeviceDriver::kNone;
  nav::LocalNavigatorOptions& navigator = config.mission.navigator;
  navigator.follower.max_linear_mps = options.max_speed_mps;
  navigator.avoid.max_linear_mps = options.max_speed_mps;
  // Backing away is the laser's to allow: the graph takes it away without one (a forward camera cannot see behind).
  navigator.evade.max_reverse_mps = options.max_speed_mps;
  navigator.learned = options.morp_il;
  navigator.direction = options.takiguchi;
  navigator.takiguchi = DirectionOptions(options);
  navigator.teach = options.teach;
  config.tracking.enabled = policy != Policy::kVoxelReactive && (sim.laser.enabled || options.camera_tracking);
  config.tracking.camera = options.camera_tracking;
  server::ApplyDerivedOptions(config);
  return config;
}

// Posts the mission to `goal` through the graph's API, as a building system does; returns the HTTP status.
int PostMission(server::Graph& graph, const Eigen::Vector2d& goal) {
  server::Request request{server::http::verb::post, "/api/v1/missions", 11};
  request.set(server::http::field::content_type, "application/json");
  request.body() = nlohmann::json{{"waypoints", {{{"x", goal.x()}, {"y", goal.y()}}}}}.dump();
  request.prepare_payload();
  std::optional<int> status;
  graph.api().Handle(request, [&status](server::Response response) { status = response.result_int(); });
  while (!status) {
    if (graph.executors().RunUntilIdle() == 0 && !status) return 0;
  }
  return *status;
}

// Per frame: the depth front end's, the local policy's and the tracker's work, read from the nodes' own loop counters
// (wall time on this computer) whenever a new frame has gone through the graph.
class FrameTimes {
 public:
  explicit FrameTimes(server::Graph& graph) : bus_(graph.bus()) {
    for (const auto& node : graph.lifecycle().nodes()) {
      if (node->name() == "ground") front_end_ = &node->Loop("frame");
      if (node->name() == "mission") policy_ = &node->Loop("frame");
      if (node->name() == "tracking")
        tracking_ = &node->Loop(graph.config().sim.robot.laser.enabled ? "scan" : "frame");
    }
  }
  // Adds this step's new frame's times, if a frame went through; true when one did.
  bool Collect(RunResult& result) {
    if (tracking_ != nullptr) {
      const auto t = tracking_->snapshot();
      if (t.loops > tracked_) {
        tracked_ = t.loops;
        result.tracking_ms.push_back(t.last_ms);
      }
    }
    const auto ground = bus_.Get(server::topics::kGroundLanes).latest();
    if (!ground || ground->frame_sequence == sequence_) return false;
    sequence_ = ground->frame_sequence;
    const auto decided = policy_->snapshot();
    if (decided.loops == decided_) return false;  // no mission step on this frame (no path yet)
    decided_ = decided.loops;
    result.depth_ms.push_back(front_end_->snapshot().last_ms);
    result.policy_ms.push_back(decided.last_ms);
    return true;
  }

 private:
  Bus& bus_;
  server::LoopStats* front_end_ = nullptr;
  server::LoopStats* policy_ = nullptr;
  server::LoopStats* tracking_ = nullptr;
  std::uint64_t sequence_ = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t decided_ = 0;
  std::uint64_t tracked_ = 0;
};

template <typename Fn>
auto Sample(Fn&& fn, int attempts) -> decltype(fn()) {
  for (int i = 0; i < attempts; ++i) {
    if (auto value = fn()) return value;
  }
  return std::nullopt;
}

}  // namespace

namespace {

// The one of `values` whose ToString is `name`.
template <typename Enum>
std::optional<Enum> FromName(const std::string& name, std::initializer_list<Enum> values) {
  for (const Enum value : values) {
    if (name == ToString(value)) return value;
  }
  return std::nullopt;
}

}  // namespace

const char* ToString(CrowdKind kind) {
  switch (kind) {
    case CrowdKind::kPaper: return "paper";
    case CrowdKind::kPacing: return "pacing";
  }
  return "unknown";
}

std::optional<CrowdKind> ParseCrowdKind(const std::string& name) {
  return FromName(name, {CrowdKind::kPaper, CrowdKind::kPacing});
}

const char* ToString(SettingKind kind) {
  switch (kind) {
    case SettingKind::kRoom: return "room";
    case SettingKind::kCorridor: return "corridor";
    case SettingKind::kOpen: return "open";
  }
  return "unknown";
}

std::optional<SettingKind> ParseSettingKind(const std::string& name) {
  return FromName(name, {SettingKind::kRoom, SettingKind::kCorridor, SettingKind::kOpen});
}

const char* ToString(ObstacleSize size) {
  switch (size) {
    case ObstacleSize::kDpoom: return "dpoom";
    case ObstacleSize::kLow: return "low";
    case ObstacleSize::kMedium: return "medium";
    case ObstacleSize::kLarge: return "large";
  }
  return "unknown";
}

std::optional<ObstacleSize> ParseObstacleSize(const std::string& name) {
  return FromName(name, {ObstacleSize::kDpoom, ObstacleSize::kLow, ObstacleSize::kMedium, ObstacleSize::kLarge});
}

const char* ToString(Outcome outcome) {
  switch (outcome) {
    case Outcome::kSuccess: return "success";
    case Outcome::kCollision: return "collision";
    case Outcome::kTimeout: return "timeout";
    case Outcome::kNoPath: return "no_path";
  }
  return "unknown";
}

bool InCameraView(const nav::OccupancyGrid& grid, const drivers::sim::SimCameraOptions& camera, const nav::Pose2& pose,
                  const Eigen::Vector2d& p) {
  const nav::SensorView view{pose * nav::Pose2{camera.mount_x_m, 0.0, 0.0},
                             0.5 * camera.horizontal_fov_deg * std::numbers::pi / 180.0, camera.max_range_m};
  if (!view.Covers(p, 0.0)) return false;
  const Eigen::Vector2d from = view.world_T_sensor.translation();
  const Eigen::Vector2d ray = p - from;
  const double range = ray.norm();
  const int samples = static_cast<int>(std::ceil(range / (0.5 * grid.resolution_m())));
  for (int i = 1; i < samples; ++i) {
    const auto cell = grid.WorldToCell(from + ray * (static_cast<double>(i) / samples));
    if (cell && grid.at(*cell) >= nav::kOccupiedCell) return false;
  }
  return true;
}

Layout MakeLayout(const ScenarioOptions& options, int world_index, int run_index) {
  Layout layout;
  layout.world_index = world_index;
  layout.run_index = run_index;
  layout.seed = static_cast<std::uint32_t>(options.seed * 7919u + static_cast<std::uint32_t>(world_index) * 101u +
                                           static_cast<std::uint32_t>(run_index));
  layout.world = BaseWorld(options, world_index, layout.map);
  const nav::OccupancyGrid& grid = layout.world.collision;
  std::mt19937 rng = Rng(options.seed, world_index, run_index);
  const double res = grid.resolution_m();
  std::uniform_real_distribution<double> ux(grid.origin().x_m, grid.origin().x_m + grid.width() * res);
  std::uniform_real_distribution<double> uy(grid.origin().y_m, grid.origin().y_m + grid.height() * res);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // Start and goal: free with room around them, 7 to 11 m apart, joined by a path on the robot's map.
  const double margin = kRobotRadiusM + 0.3;
  const nav::Costmap map_costmap = RobotCostmap(layout.map);
  const auto pair = Sample(
      [&]() -> std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> {
        const Eigen::Vector2d start(ux(rng), uy(rng));
        if (!Clear(grid, start, margin) || !Clear(layout.map, start, margin)) return std::nullopt;
        const double a = angle(rng);
        const double d = options.min_goal_m + unit(rng) * (options.max_goal_m - options.min_goal_m);
        const Eigen::Vector2d goal = start + d * Eigen::Vector2d(std::cos(a), std::sin(a));
        if (!Clear(grid, goal, margin) || !PathExists(map_costmap, start, goal)) return std::nullopt;
        return std::pair{start, goal};
      },
      2000);
  if (!pair) throw std::runtime_error("no start and goal 7-11 m apart with a path between them in this world");
  const auto [start, goal] = *pair;
  layout.goal = goal;
  const Eigen::Vector2d way = goal - start;
  const Eigen::Vector2d across(-way.y() / way.norm(), way.x() / way.norm());
  // Facing the goal, as DPoom's evaluation starts the robot; with the pacing crowd, facing it roughly (within 30
  // degrees), as a robot would after turning to its path.
  const double heading_offset = (unit(rng) - 0.5) * std::numbers::pi / 3.0;
  layout.start = {start.x(), start.y(),
                  std::atan2(way.y(), way.x()) + (options.crowd == CrowdKind::kPaper ? 0.0 : heading_offset)};

  // Static obstacles near the way (so that they matter), apart enough for the robot to pass between them, never
  // closing the way: each is kept only while a path remains.
  std::vector<StaticObstacle> obstacles;
  for (int i = 0; i < options.static_obstacles; ++i) {
    const auto obstacle = Sample(
        [&]() -> std::optional<StaticObstacle> {
          StaticObstacle o;
          o.shape = unit(rng) < 0.5 ? StaticObstacle::Shape::kCylinder : StaticObstacle::Shape::kBox;
          // Radius or half side, and height.
          const auto [half, height] = [&] {
            switch (options.obstacle_size) {
              case ObstacleSize::kLow: return std::pair{0.15, 0.15};
              case ObstacleSize::kMedium: return std::pair{0.25, 0.5};
              case ObstacleSize::kLarge: return std::pair{0.6, 1.2};
              case ObstacleSize::kDpoom: break;
            }
            return std::pair{0.5, 1.0};
          }();
          o.size_m = half;
          o.height_m = height;
          o.yaw_rad = angle(rng);
          o.center = start + (0.15 + 0.7 * unit(rng)) * way + (unit(rng) - 0.5) * 3.0 * across;
          const double r = o.bounding_radius_m();
          if ((o.center - start).norm() < r + 1.0 || (o.center - goal).norm() < r + 1.0) return std::nullopt;
          if (!Clear(grid, o.center, r + 0.1)) return std::nullopt;
          for (const StaticObstacle& other : obstacles) {
            if ((other.center - o.center).norm() < r + other.bounding_radius_m() + 2.0 * kRobotRadiusM + 0.3) {
              return std::nullopt;
            }
          }
          World trial_world;
          trial_world.collision = grid;
          std::vector<StaticObstacle> trial = obstacles;
          trial.push_back(o);
          drivers::sim::AddObstacles(trial_world, trial);
          if (!PathExists(RobotCostmap(trial_world.collision), start, goal)) return std::nullopt;
          return o;
        },
        200);
    if (obstacle) obstacles.push_back(*obstacle);
  }
  drivers::sim::AddObstacles(layout.world, obstacles);

  layout.crowd.radius_m = kPersonRadiusM;
  layout.crowd.see_robot = options.people_see_robot;
  drivers::sim::RouteArea area;
  if (options.crowd == CrowdKind::kPaper) {
    // In the area the robot must cross, 3 to 7 m before its goal (and at least 1.5 m ahead of the robot), within
    // 2.5 m of the straight way; walked once, slowly, then stood at.
    const double length = way.norm();
    const Eigen::Vector2d along = way / length;
    const double near = std::max(1.5, length - 7.0);
    const double far = length - 3.0;
    constexpr double kHalfWidthM = 2.5;
    area.center = start + 0.5 * (near + far) * along;
    area.within_m = std::hypot(0.5 * (far - near), kHalfWidthM);
    area.min_length_m = 2.5;
    area.max_length_m = 5.0;
    area.contains = [start, along, across, near, far](const Eigen::Vector2d& p) {
      const double a = (p - start).dot(along);
      return a >= near && a <= far && std::abs((p - start).dot(across)) <= kHalfWidthM;
    };
    area.goals_apart = true;
    layout.crowd.preferred_speed_mps = 0.35;
    layout.crowd.max_speed_mps = 0.35;
    layout.crowd.turn_back = false;
  } else {
    // Anywhere in the world, not starting near the robot: they cross the robot's way when their routes happen to.
    area.center = start;
    area.clearance_m = 2.0;
  }
  layout.routes = drivers::sim::RandomRoutes(layout.world.collision, options.pedestrians, kPersonRadiusM, area, rng);
  return layout;
}

RunResult RunOnce(const Layout& layout, Policy policy, const ScenarioOptions& options) {
  RunResult result;
  result.policy = policy;
  result.world_index = layout.world_index;
  result.run_index = layout.run_index;
  result.seed = layout.seed;

  drivers::sim::SimOptions sim;
  sim.start = layout.start;
  sim.seed = layout.seed;
  sim.camera.rate_hz = options.camera_rate_hz;
  sim.laser.enabled = options.laser && policy != Policy::kVoxelReactive;
  sim.stereo.enabled = options.stereo;
  if (options.stereo && options.mmsvf) sim.stereo.wide_baseline_m = 0.24;
  sim.pan.enabled = options.pan;
  sim.pedestrians = layout.routes;
  sim.crowd = layout.crowd;
  sim.base.limits.footprint_radius_m = kRobotRadiusM;
  drivers::sim::SimRobot robot(std::make_shared<const World>(layout.world), sim);

  // The daemon's own graph, in lockstep with the simulator, in a state directory of its own.
  const StateDir state_dir;
  const server::Config config = GraphConfig(sim, policy, options, state_dir.path());
  server::Devices devices{&robot, robot, sim.laser.enabled ? &robot : nullptr, &robot, &robot, nullptr};
  if (options.pan) devices.pan = &robot;
  server::Graph graph(config, devices, server::NamedMap{"scenario", layout.map}, server::Schedule::kLockstep);
  graph.Start();
  // The simulator's people for a privileged expert, for this run only.
  struct Privilege {
    nav::Demonstrations* teach;
    ~Privilege() {
      if (teach != nullptr) teach->people = nullptr;
    }
  } privilege{options.privileged ? options.teach.get() : nullptr};
  if (privilege.teach != nullptr) {
    privilege.teach->people = [&robot] {
      std::vector<nav::TrackedObject> people;
      for (const drivers::sim::Pedestrian& p : robot.pedestrians()) {
        nav::TrackedObject o;
        o.position = p.position;
        o.velocity = p.velocity;
        o.radius_m = kPersonRadiusM;
        o.moving = p.velocity.norm() > 0.0;
        people.push_back(o);
      }
      return people;
    };
  }
  FrameTimes times(graph);
  Bus& bus = graph.bus();
  if (options.trace) {
    std::fprintf(stderr, "run world %d run %d start %.2f %.2f goal %.2f %.2f\n", layout.world_index, layout.run_index,
                 layout.start.x_m, layout.start.y_m, layout.goal.x(), layout.goal.y());
  }
  // The mission, posted as a building system would: POST /api/v1/missions.
  const int status = PostMission(graph, layout.goal);
  if (status != 201) {
    result.outcome = Outcome::kNoPath;
    return result;
  }

  const double straight = (layout.goal - layout.start.translation()).norm();
  const double timeout_s = options.timeout_s > 0.0 ? options.timeout_s : 3.0 * straight / options.max_speed_mps + 20.0;
  nav::Pose2 last = layout.start;
  std::vector<double> last_in_view;  // per person: the simulated time they were last in the camera's view, -1 never
  while (true) {
    graph.Step();
    const double now_s = drivers::ToSeconds(robot.now_ns());
    const nav::Pose2 pose = robot.true_pose();
    const Eigen::Vector2d robot_velocity = (pose.translation() - last.translation()) / robot.step_s();
    result.path_length_m += (pose.translation() - last.translation()).norm();
    last = pose;
    const auto people = robot.pedestrians();
    last_in_view.resize(people.size(), -1.0);
    for (std::size_t i = 0; i < people.size(); ++i) {
      result.closest_person_m = std::min(
          result.closest_person_m, (people[i].position - pose.translation()).norm() - kRobotRadiusM - kPersonRadiusM);
      if (InCameraView(layout.world.collision, sim.camera, pose, people[i].position)) last_in_view[i] = now_s;
    }
    result.time_s = now_s;
    if (const auto mission = bus.Get(server::topics::kMission).latest();
        mission && mission->status == nav::MissionStatus::kFailed) {
      result.outcome = Outcome::kNoPath;
      break;
    }
    if (robot.bumper_pressed()) {
      result.outcome = Outcome::kCollision;
      const auto person = std::find_if(people.begin(), people.end(), [&](const drivers::sim::Pedestrian& p) {
        return (p.position - pose.translation()).norm() <= kRobotRadiusM + kPersonRadiusM + 0.02;
      });
      result.collided_with = person != people.end() ? "person" : "wall or obstacle";
      result.robot_drove_into_it = true;
      if (person != people.end()) {
        // Closing speeds along the line between them: who walked into whom.
        const Eigen::Vector2d toward = (person->position - pose.translation()).normalized();
        const double robot_closing = robot_velocity.dot(toward);
        result.robot_drove_into_it = robot_closing > 0.02 && robot_closing >= -person->velocity.dot(toward);
        const double seen = last_in_view[static_cast<std::size_t>(person - people.begin())];
        result.person_in_view_s = seen >= 0.0 ? std::optional<double>(now_s - seen) : std::nullopt;
      }
      if (options.trace) {
        const auto step = bus.Get(server::topics::kLocalStep).latest();
        TraceCollision(layout, pose, people, step ? step->remembered : std::vector<Eigen::Vector2d>{});
      }
      break;
    }
    const double to_goal_m = (pose.translation() - layout.goal).norm();
    if (options.until_arrived) {
      if (const auto mission = bus.Get(server::topics::kMission).latest();
          mission && mission->status == nav::MissionStatus::kSucceeded) {
        result.outcome = Outcome::kSuccess;
        result.final_error_m = to_goal_m;
        break;
      }
    } else if (to_goal_m <= options.goal_tolerance_m) {
      result.outcome = Outcome::kSuccess;
      break;
    }
    if (now_s > timeout_s) {
      result.outcome = Outcome::kTimeout;
      break;
    }
    if (times.Collect(result) && options.trace) {
      const auto step = bus.Get(server::topics::kLocalStep).latest();
      const auto ground = bus.Get(server::topics::kGroundLanes).latest();
      const auto tracked = bus.Get(server::topics::kTrackedObjects).latest();
      if (step && ground && step->stamp_ns == robot.now_ns()) {
        TraceDecision(now_s, pose, step->step, ground->lanes, tracked ? &tracked->surroundings : nullptr, people,
                      step->remembered);
      }
    }
  }
  graph.Stop();
  return result;
}

std::vector<RunResult> RunAll(const ScenarioOptions& options, const std::function<void(const RunResult&)>& progress) {
  std::vector<RunResult> results;
  for (int w = 0; w < options.worlds; ++w) {
    for (int r = 0; r < options.runs; ++r) {
      if (options.only && *options.only != std::pair{w, r}) continue;
      const Layout layout = MakeLayout(options, w, r);
      for (Policy policy : options.policies) {
        results.push_back(RunOnce(layout, policy, options));
        if (progress) progress(results.back());
      }
    }
  }
  return results;
}

std::vector<PolicySummary> Summarise(const std::vector<RunResult>& results) {
  std::map<Policy, std::vector<const RunResult*>> by_policy;
  for (const RunResult& r : results) by_policy[r.policy].push_back(&r);
  std::vector<PolicySummary> out;
  for (const auto& [policy, runs] : by_policy) {
    PolicySummary s;
    s.policy = policy;
    s.runs = static_cast<int>(runs.size());
    int successes = 0;
    double time = 0.0;
    double path = 0.0;
    int with_people = 0;
    double closest = 0.0;
    double least = std::numeric_limits<double>::infinity();
    std::vector<double> totals;
    double final_errors = 0.0;
    int arrived = 0;
    double tracking = 0.0;
    double depth = 0.0;
    double decide = 0.0;
    for (const RunResult* r : runs) {
      if (r->outcome == Outcome::kSuccess) {
        ++successes;
        time += r->time_s;
        path += r->path_length_m;
      }
      if (r->final_error_m) {
        ++arrived;
        final_errors += *r->final_error_m;
        s.max_final_error_m = std::max(s.max_final_error_m.value_or(0.0), *r->final_error_m);
      }
      if (std::isfinite(r->closest_person_m)) {
        ++with_people;
        closest += r->closest_person_m;
        least = std::min(least, r->closest_person_m);
      }
      s.collision += r->outcome == Outcome::kCollision ? 1.0 : 0.0;
      s.robot_collision += r->outcome == Outcome::kCollision && r->robot_drove_into_it ? 1.0 : 0.0;
      s.timeout += r->outcome == Outcome::kTimeout ? 1.0 : 0.0;
      for (const double t : r->tracking_ms) tracking += t;
      s.scans += r->tracking_ms.size();
      for (std::size_t i = 0; i < r->depth_ms.size(); ++i) {
        depth += r->depth_ms[i];
        decide += r->policy_ms[i];
        totals.push_back(r->depth_ms[i] + r->policy_ms[i]);
      }
    }
    s.success = static_cast<double>(successes) / s.runs;
    s.collision /= s.runs;
    s.robot_collision /= s.runs;
    s.timeout /= s.runs;
    s.mean_time_to_goal_s = successes > 0 ? time / successes : 0.0;
    s.mean_path_length_m = successes > 0 ? path / successes : 0.0;
    if (with_people > 0) {
      s.mean_closest_person_m = closest / with_people;
      s.min_closest_person_m = least;
    }
    if (arrived > 0) s.mean_final_error_m = final_errors / arrived;
    s.frames = totals.size();
    if (s.scans > 0) s.tracking_ms = tracking / static_cast<double>(s.scans);
    if (!totals.empty()) {
      const double n = static_cast<double>(totals.size());
      s.depth_ms = depth / n;
      s.policy_ms = decide / n;
      s.total_ms = s.depth_ms + s.policy_ms;
      std::sort(totals.begin(), totals.end());
      s.total_p99_ms = totals[static_cast<std::size_t>(0.99 * (n - 1))];
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace corridor::scenario
