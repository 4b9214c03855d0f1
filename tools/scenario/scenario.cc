#include "tools/scenario/scenario.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>

#include "drivers/sim/sim_robot.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/morp.h"
#include "nav/ground/voxel_obstacles.h"
#include "nav/planner/planner.h"
#include "nav/policy/evasion.h"
#include "nav/policy/local_navigator.h"
#include "nav/policy/reactive.h"
#include "nav/tracking/moving_objects.h"
#include "nav/tracking/traffic_map.h"

namespace corridor::scenario {
namespace {

using drivers::sim::PedestrianRoute;
using drivers::sim::StaticObstacle;
using drivers::sim::World;

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
  std::uniform_real_distribution<double> size(12.0, 15.0);
  const double width = size(rng);
  const double height = size(rng);
  map = drivers::sim::RoomMap(width, height, kRoomResolutionM);
  return drivers::sim::WorldFromMap(map, drivers::sim::WorldOptions{});
}

// --trace output: one line per morp-rb decision, and what surrounded a collision.
void TraceDecision(double now_s, const nav::Pose2& pose, const nav::LocalStep& step,
                   const std::vector<nav::LaneResult>& lanes, const nav::Surroundings* around,
                   const std::vector<drivers::sim::Pedestrian>& people) {
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
    std::fprintf(stderr, "  obstacle %s at %.2f %.2f size %.2f, distance %.2f\n",
                 o.shape == StaticObstacle::Shape::kBox ? "box" : "cylinder", o.center.x(), o.center.y(), o.size_m,
                 (o.center - pose.translation()).norm());
  }
  std::fprintf(stderr, "  remembered within 1 m (robot frame):");
  for (const Eigen::Vector2d& p : remembered) {
    const Eigen::Vector2d local = pose.Inverse().Transform(p);
    if (local.norm() <= 1.0) std::fprintf(stderr, " (%.2f %.2f)", local.x(), local.y());
  }
  std::fprintf(stderr, "\n");
}

template <typename Fn>
auto Sample(Fn&& fn, int attempts) -> decltype(fn()) {
  for (int i = 0; i < attempts; ++i) {
    if (auto value = fn()) return value;
  }
  return std::nullopt;
}

}  // namespace

const char* ToString(Policy policy) {
  switch (policy) {
    case Policy::kMorpRb: return "morp-rb";
    case Policy::kVoxelReactive: return "voxel-reactive";
  }
  return "unknown";
}

std::optional<Policy> ParsePolicy(const std::string& name) {
  for (Policy p : {Policy::kMorpRb, Policy::kVoxelReactive}) {
    if (name == ToString(p)) return p;
  }
  return std::nullopt;
}

const char* ToString(CrowdKind kind) {
  switch (kind) {
    case CrowdKind::kPaper: return "paper";
    case CrowdKind::kPacing: return "pacing";
  }
  return "unknown";
}

std::optional<CrowdKind> ParseCrowdKind(const std::string& name) {
  for (CrowdKind k : {CrowdKind::kPaper, CrowdKind::kPacing}) {
    if (name == ToString(k)) return k;
  }
  return std::nullopt;
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
          o.size_m = 0.5;
          o.height_m = 1.0;
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
  sim.laser.enabled = options.laser && policy == Policy::kMorpRb;
  sim.pedestrians = layout.routes;
  sim.crowd = layout.crowd;
  sim.base.limits.footprint_radius_m = kRobotRadiusM;
  drivers::sim::SimRobot robot(std::make_shared<const World>(layout.world), sim);
  std::shared_ptr<const drivers::RgbdFrame> pending;
  robot.SetFrameHandler([&pending](std::shared_ptr<drivers::RgbdFrame> frame) { pending = std::move(frame); });
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  // morp-rb tracks moving objects: with the laser, its scans feed the tracker as they come (the simulator calls back
  // inside Step, at the scan's pose); without, each depth frame's scan does (below).
  const bool tracking = policy == Policy::kMorpRb && (sim.laser.enabled || options.camera_tracking);
  nav::MovingObjectTracker tracker{sim.laser.enabled ? nav::MovingObjectOptions{}
                                                    : nav::ForDepthCamera(nav::MovingObjectOptions{})};
  const nav::Surroundings* around = nullptr;
  std::optional<nav::TrafficMap> traffic;
  nav::TrafficOptions traffic_options;
  if (tracking && traffic_options.weight > 0.0) traffic.emplace(layout.map, traffic_options);
  if (tracking) {
    tracker.SetMap(std::make_shared<const nav::OccupancyGrid>(layout.map));
    around = &tracker.surroundings();
  }
  // One scan (world frame) into the tracker and the traffic map, timed: `points` is made by the caller inside `t0`.
  const auto track = [&](Clock::time_point t0, double stamp_s, const Eigen::Vector2d& sensor,
                         const std::vector<Eigen::Vector2d>& points, const std::optional<nav::SensorView>& view) {
    tracker.Update(stamp_s, sensor, points, view);
    if (traffic) traffic->Add(stamp_s, tracker.objects());
    result.tracking_ms.push_back(ms(t0, Clock::now()));
  };
  if (sim.laser.enabled) {
    robot.SetScanHandler([&](std::shared_ptr<const drivers::LaserScan> scan) {
      const auto t0 = Clock::now();
      const nav::Pose2 laser = robot.true_pose() * robot.base_T_laser();
      track(t0, drivers::ToSeconds(scan->stamp_ns), laser.translation(),
            nav::ScanToWorld(laser, scan->angle_min_rad, scan->angle_increment_rad, scan->range_min_m,
                             scan->range_max_m, scan->ranges),
            std::nullopt);
    });
  }
  const nav::PinholeCamera camera = robot.info().camera;
  std::optional<nav::DepthScan> depth_scan;
  if (tracking && !sim.laser.enabled) depth_scan.emplace(camera, nav::DepthScanOptions{});
  // morp-rb's obstacle memory takes each frame's whole scan (the image's sides kept), as the daemon's ground node
  // gives it: part of the depth processing.
  nav::DepthScan memory_scan(camera, nav::ForObstacleMemory(nav::DepthScanOptions{}));
  const nav::SensorView memory_view = memory_scan.View(nav::Pose2{});

  const auto costmap = std::make_shared<const nav::Costmap>(RobotCostmap(layout.map));
  nav::LocalNavigatorOptions navigator_options;
  navigator_options.follower.max_linear_mps = options.max_speed_mps;
  navigator_options.avoid.max_linear_mps = options.max_speed_mps;
  navigator_options.avoid.front_offset_m = kRobotRadiusM;
  navigator_options.memory.robot_radius_m = kRobotRadiusM;
  navigator_options.evade.robot_radius_m = kRobotRadiusM;
  navigator_options.evade.max_linear_mps = options.max_speed_mps;
  // Backing away is the laser's to allow: a forward camera cannot see what is behind.
  navigator_options.evade.max_reverse_mps = options.max_speed_mps;
  if (!sim.laser.enabled) navigator_options.evade = nav::ForForwardView(navigator_options.evade);
  // Round where people walk, and round what blocked the robot (`blocking`: LocalNavigator::Blocking).
  const auto plan_from = [&](const Eigen::Vector2d& from, const std::vector<Eigen::Vector2d>& blocking) {
    nav::PathOptions path_options;
    std::vector<float> extra;
    const double now_s = drivers::ToSeconds(robot.now_ns());
    if (traffic && !traffic->Empty(now_s)) extra = traffic->StepCost(now_s);
    if (!blocking.empty()) {
      nav::AddPointCost(*costmap, blocking, navigator_options.blocked_radius_m,
                        static_cast<float>(navigator_options.blocked_cost), extra);
    }
    path_options.extra_cost = extra;
    path_options.robot_at_start = true;
    return nav::PlanPath(*costmap, from, layout.goal, std::nullopt, nullptr, path_options);
  };
  if (options.trace) {
    std::fprintf(stderr, "run world %d run %d start %.2f %.2f goal %.2f %.2f\n", layout.world_index, layout.run_index,
                 layout.start.x_m, layout.start.y_m, layout.goal.x(), layout.goal.y());
  }
  double planned_s = 0.0;
  nav::PlanResult plan = plan_from(layout.start.translation(), {});
  if (!plan.ok()) {
    result.outcome = Outcome::kNoPath;
    return result;
  }

  nav::LocalNavigator navigator(navigator_options);
  navigator.SetPath(plan.plan.waypoints, costmap);
  nav::Morp morp(camera, nav::MorpOptions{});

  nav::PathFollower follower(navigator_options.follower);
  follower.SetPath(plan.plan.waypoints);
  nav::VoxelObstacles voxels(camera, nav::VoxelObstacleOptions{});
  nav::ReactiveOptions reactive;
  reactive.max_linear_mps = options.max_speed_mps;
  reactive.front_offset_m = kRobotRadiusM;

  const double straight = (layout.goal - layout.start.translation()).norm();
  const double timeout_s = options.timeout_s > 0.0 ? options.timeout_s : 3.0 * straight / options.max_speed_mps + 20.0;
  nav::Pose2 last = layout.start;
  double last_frame_s = 0.0;
  while (true) {
    robot.Step();
    const double now_s = drivers::ToSeconds(robot.now_ns());
    const nav::Pose2 pose = robot.true_pose();
    const Eigen::Vector2d robot_velocity = (pose.translation() - last.translation()) / robot.step_s();
    result.path_length_m += (pose.translation() - last.translation()).norm();
    last = pose;
    result.time_s = now_s;
    if (robot.bumper_pressed()) {
      result.outcome = Outcome::kCollision;
      const auto people = robot.pedestrians();
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
      }
      if (options.trace) TraceCollision(layout, pose, people, navigator.Remembered());
      break;
    }
    if ((pose.translation() - layout.goal).norm() <= options.goal_tolerance_m) {
      result.outcome = Outcome::kSuccess;
      break;
    }
    if (now_s > timeout_s) {
      result.outcome = Outcome::kTimeout;
      break;
    }
    if (!pending) continue;
    const std::shared_ptr<const drivers::RgbdFrame> frame = std::move(pending);
    pending = nullptr;
    const double dt_s = now_s - last_frame_s;
    last_frame_s = now_s;
    if (depth_scan) {
      // Tracking from the depth frame, as the daemon's tracking node does beside the control loop: not in the
      // per-frame times.
      const auto t_scan = Clock::now();
      std::vector<Eigen::Vector2d> points;
      for (const Eigen::Vector2d& p : depth_scan->Process(frame->depth_mm)) points.push_back(pose.Transform(p));
      const nav::SensorView view = depth_scan->View(pose);
      track(t_scan, now_s, view.world_T_sensor.translation(), points, view);
    }
    nav::Twist2 twist;
    std::optional<nav::LocalStep> step;  // morp-rb's, for --trace after the timings
    const auto t0 = Clock::now();
    Clock::time_point t1;
    if (policy == Policy::kMorpRb) {
      const std::vector<nav::LaneResult>& lanes = morp.Process(frame->depth_mm);
      const std::vector<Eigen::Vector2d>& seen = memory_scan.Process(frame->depth_mm);
      t1 = Clock::now();
      navigator.See(pose, seen, memory_view);
      step = navigator.Update(pose, lanes, std::numeric_limits<double>::infinity(), dt_s, around);
      if (step->replan || step->blocked) {
        plan = plan_from(pose.translation(), navigator.Blocking());
        if (plan.ok()) navigator.SetPath(plan.plan.waypoints, costmap);
        planned_s = now_s;
        if (options.trace && step->blocked) {
          // Where the new path leads: its length, and its point 1 m on, in the robot's frame.
          Eigen::Vector2d ahead = Eigen::Vector2d::Zero();
          double along = 0.0;
          for (std::size_t i = 1; plan.ok() && i < plan.plan.dense.size() && along < 1.0; ++i) {
            along += (plan.plan.dense[i] - plan.plan.dense[i - 1]).norm();
            ahead = pose.Inverse().Transform(plan.plan.dense[i]);
          }
          std::fprintf(stderr, "t %.2f blocked: planned round what it saw (%zu points): %.1f m, 1 m on at %.2f %.2f\n",
                       now_s, navigator.Blocking().size(), plan.ok() ? plan.plan.length_m : -1.0, ahead.x(), ahead.y());
        }
      }
      twist = step->twist;
    } else {
      const std::vector<Eigen::Vector2f>& obstacles = voxels.Process(frame->depth_mm);
      t1 = Clock::now();
      const nav::FollowStep follow = follower.Update(pose, std::numeric_limits<double>::infinity());
      if (follow.off_path_m > navigator_options.replan_distance_m) {
        plan = plan_from(pose.translation(), {});
        if (plan.ok()) follower.SetPath(plan.plan.waypoints);
      }
      const Eigen::Vector2d to_target = follow.target - pose.translation();
      twist = nav::ReactiveCommand(obstacles, std::atan2(to_target.y(), to_target.x()) - pose.yaw_rad, reactive);
    }
    const auto t2 = Clock::now();
    result.depth_ms.push_back(ms(t0, t1));
    result.policy_ms.push_back(ms(t1, t2));
    // People's ways change the best path: plan again now and then and take a path that goes elsewhere (the
    // planner's work, as in the daemon, where it runs beside the control loop: not in the per-frame times).
    if (traffic && !traffic->Empty(now_s) && navigator_options.reroute_s > 0.0 &&
        now_s - planned_s >= navigator_options.reroute_s) {
      nav::PlanResult again = plan_from(pose.translation(), navigator.Blocking());
      if (again.ok() && (!plan.ok() || nav::PathsDiverge(again.plan.dense, plan.plan.dense,
                                                          navigator_options.reroute_look_m,
                                                          navigator_options.reroute_tolerance_m))) {
        plan = std::move(again);
        navigator.SetPath(plan.plan.waypoints, costmap);
      }
      planned_s = now_s;
    }
    if (options.trace && step) TraceDecision(now_s, pose, *step, morp.results(), around, robot.pedestrians());
    robot.SetVelocity(twist);
  }
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
    std::vector<double> totals;
    double tracking = 0.0;
    double depth = 0.0;
    double decide = 0.0;
    for (const RunResult* r : runs) {
      if (r->outcome == Outcome::kSuccess) {
        ++successes;
        time += r->time_s;
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
