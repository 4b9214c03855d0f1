#include "nav/policy/local_navigator.h"

#include "nav/planner/planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace corridor::nav {

LocalNavigator::LocalNavigator(const LocalNavigatorOptions& options)
    : options_(options),
      follower_(options.follower),
      avoid_(options.avoid),
      memory_(options.memory),
      evade_(options.evade),
      features_(options.il),
      flmc_(options.fuzzy_policy ? std::make_unique<Flmc>(options.flmc) : nullptr) {
  if (options.learned) CheckMorpIlNetwork(*options.learned, options.il);
  if (options.direction_policy) {
    CheckTakiguchiOptions(options.takiguchi);
    if (options.direction) CheckTakiguchiNetwork(*options.direction, options.takiguchi);
    if (!options.direction && !options.teach) {
      throw std::invalid_argument("local navigator: Takiguchi's policy needs its network (or, training, teach)");
    }
  }
  if (!(options.stuck_s >= 0.0) || !(options.stuck_distance_m > 0.0) || !(options.blocked_radius_m >= 0.0) ||
      !(options.blocked_cost >= 0.0) || !(options.blocked_hold_s >= 0.0) || !(options.reorient_done_rad > 0.0) ||
      !(options.reorient_max_s >= 0.0)) {
    throw std::invalid_argument(
        "local navigator: need stuck_s >= 0, stuck_distance_m > 0, reorient_done_rad > 0, and blocked_radius_m, "
        "blocked_cost, blocked_hold_s and reorient_max_s >= 0");
  }
}

void LocalNavigator::SetPath(std::vector<Waypoint> path, std::shared_ptr<const Costmap> map) {
  // A path the planner gave as a way out of the map's inflated band (it crosses the band, at the band's crawl) is
  // followed there by the band's rules.
  std::optional<Eigen::Vector2d> band_from;
  const bool crawls =
      std::any_of(path.begin(), path.end(), [](const Waypoint& w) { return w.speed_limit_mps <= kBandSpeedMps; });
  if (map && crawls && !RestOfPathTraversable(*map, path, path.front().pose.translation(), 0.0)) {
    band_from = path.front().pose.translation();
  }
  memory_.SetBandCrossing(band_from);
  follower_.SetPath(std::move(path));
  SetMap(std::move(map));
  avoid_ = MorpRb(options_.avoid);  // a new path: no side committed, no overtaking in progress
  features_.Clear();
  headway_from_.reset();  // and stuck_s to make headway on it
  // The first path after a blocked way may lead off another way: turn to it on the spot first.
  reorient_s_ = reorient_next_path_ ? 0.0 : -1.0;
  reorient_next_path_ = false;
}

LocalStep LocalNavigator::Update(const Pose2& robot, const FrameView& frame, double speed_limit_mps, double dt_s,
                                 const Surroundings* around) {
  if (frame.scan != nullptr && frame.scan_view.range_m > 0.0) See(robot, *frame.scan, frame.scan_view);
  static const std::vector<LaneResult> kNone;
  return Update(robot, frame.lanes != nullptr ? *frame.lanes : kNone, speed_limit_mps, dt_s, around);
}

LocalStep LocalNavigator::Update(const Pose2& robot, const std::vector<LaneResult>& lanes, double speed_limit_mps,
                                 double dt_s, const Surroundings* around) {
  LocalStep out;
  memory_.Update(robot, lanes, dt_s);
  if (around != nullptr) {
    // The laser tells people from furniture: what the camera saw of someone walking is not an obstacle to keep.
    for (const TrackedObject& o : around->objects) {
      if (o.moving) memory_.Forget(o.position, o.radius_m + options_.evade.min_object_radius_m);
    }
  }
  detour_left_m_ = std::max(0.0, detour_left_m_ - last_speed_mps_ * std::max(0.0, dt_s));
  const FollowStep follow = follower_.Update(robot, speed_limit_mps);
  out.remaining_m = follow.remaining_m;
  if (follow.done) {
    out.done = true;
    return out;
  }
  // Headway: farther than stuck_distance_m from where it last made some. Without it for stuck_s, the way is blocked.
  if (!headway_from_ || (robot.translation() - *headway_from_).norm() > options_.stuck_distance_m) {
    headway_from_ = robot.translation();
    without_headway_s_ = 0.0;
  } else {
    without_headway_s_ += std::max(0.0, dt_s);
  }
  blocked_s_ += std::max(0.0, dt_s);
  if (blocked_s_ > options_.blocked_hold_s) blocking_.clear();
  if (options_.stuck_s > 0.0 && without_headway_s_ >= options_.stuck_s) {
    out.blocked = true;
    without_headway_s_ = 0.0;  // asks again after another stuck_s
    blocking_ = memory_.Points();
    blocked_s_ = 0.0;
    reorient_next_path_ = true;
  }
  if (follow.off_path_m > options_.replan_distance_m) {
    out.replan = true;
    Evade(robot, robot.translation(), around, out);  // standing still is not safe from someone walking into it
    return out;
  }
  const Eigen::Vector2d to_target = follow.target - robot.translation();
  const double heading_error = WrapAngle(std::atan2(to_target.y(), to_target.x()) - robot.yaw_rad);
  if (reorient_s_ >= 0.0) {
    reorient_s_ += std::max(0.0, dt_s);
    if (std::abs(heading_error) <= options_.reorient_done_rad || reorient_s_ > options_.reorient_max_s) {
      reorient_s_ = -1.0;
    } else {
      // MORP-RB would turn toward the free lanes ahead, which is the way that blocked the robot.
      out.mode = MorpRbMode::kStopAndTurn;
      out.twist = {0.0, std::copysign(options_.avoid.max_angular_rps, heading_error)};
      const Twist2 guarded = memory_.Guard(robot, out.twist);
      out.guarded = guarded.linear_mps != out.twist.linear_mps || guarded.angular_rps != out.twist.angular_rps;
      out.twist = guarded;
      Evade(robot, follow.target, around, out);
      last_speed_mps_ = std::max(0.0, out.twist.linear_mps);
      last_command_ = out.twist;
      return out;
    }
  }
  // MORP-RB sees the lanes in the corridor with the map's own obstacles taken out; the speed, all of them.
  ahead_.clear();
  out.nearest_m = std::numeric_limits<double>::infinity();
  for (const LaneResult& lane : lanes) {
    if (std::abs(lane.offset_m) > options_.corridor_half_width_m) continue;
    ahead_.push_back(lane);
    if (!lane.dead_end) continue;
    out.nearest_m = std::min(out.nearest_m, lane.free_distance_m);
    if (OnMap(robot, lane)) ahead_.back().dead_end = false;
  }
  const MorpRbDecision decision = avoid_.Decide(ahead_, heading_error, dt_s);
  out.mode = decision.mode;
  const double v_free =
      ahead_.empty() ? 0.0
                     : SpeedForFreeDistance(out.nearest_m - options_.avoid.front_offset_m, options_.avoid.stopping);

  if (!follow.final_approach && decision.mode == MorpRbMode::kFollow && detour_left_m_ > 0.0) {
    // Away from what the memory refused, straight on.
    out.mode = MorpRbMode::kOvertake;
    out.twist = {std::min({options_.avoid.max_linear_mps, v_free, follow.speed_limit_mps}), 0.0};
  } else if (follow.final_approach || decision.mode == MorpRbMode::kFollow) {
    out.twist = follow.twist;
    if (out.twist.linear_mps > v_free) {
      // Keep the curvature: slow the turn with the speed.
      const double scale = out.twist.linear_mps > 0.0 ? v_free / out.twist.linear_mps : 0.0;
      out.twist = {v_free, out.twist.angular_rps * (follow.final_approach ? 1.0 : scale)};
    }
    out.mode = MorpRbMode::kFollow;
    if (follow.final_approach && follow.twist.linear_mps > 0.0 && v_free <= 0.0 &&
        follow.remaining_m <= options_.blocked_arrival_m) {
      follower_.AcceptPosition();
    }
  } else {
    out.avoiding = true;
    out.twist = decision.twist;
    out.twist.linear_mps = std::min(out.twist.linear_mps, follow.speed_limit_mps);
  }
  bool evade = true;
  if (options_.direction_policy) {
    if (!follow.final_approach) {
      out.twist = Direct(robot, around, follow, v_free, out);
      evade = false;
    }
  } else if (flmc_) {
    if (!follow.final_approach || follow.remaining_m > options_.flmc.stop_within_m) {
      out.twist = Fuzzy(robot, lanes, follow, v_free, out);
    }
  } else if (options_.learned || options_.teach) {
    out.twist = Imitate(robot, lanes, follow, out.twist, v_free, out);
  }
  ObstacleMemory::Blocker refused_by = ObstacleMemory::Blocker::kNone;
  const Twist2 guarded = memory_.Guard(robot, out.twist, follow.final_approach, &refused_by);
  out.guarded = guarded.linear_mps != out.twist.linear_mps || guarded.angular_rps != out.twist.angular_rps;
  // A detour drives on away from what was refused, out of the camera's view, before heading for the path again. Not
  // when only the map refused the way: the path keeps its clearance from the map, and the follower's arc cut a
  // corner of it; driving on would leave the path for a loop back to it.
  if (out.guarded && !follow.final_approach && refused_by != ObstacleMemory::Blocker::kMap) {
    detour_left_m_ = options_.detour_m;
  }
  out.twist = guarded;
  if (evade) Evade(robot, follow.target, around, out);
  last_speed_mps_ = std::max(0.0, out.twist.linear_mps);
  last_command_ = out.twist;
  return out;
}

Twist2 LocalNavigator::Direct(const Pose2& robot, const Surroundings* around, const FollowStep& follow, double v_free,
                              LocalStep& step) {
  static const Surroundings kNothing;
  const Surroundings& seen = around != nullptr ? *around : kNothing;
  const Eigen::Vector2d to_target = follow.target - robot.translation();
  const double bearing = WrapAngle(std::atan2(to_target.y(), to_target.x()) - robot.yaw_rad);
  const Eigen::VectorXf input = TakiguchiInput(robot, seen, bearing, options_.takiguchi);
  Demonstrations* teach = options_.teach.get();
  const bool expert_drives = !options_.direction || (teach != nullptr && std::uniform_real_distribution<double>(
                                                                             0.0, 1.0)(teach->random) < teach->beta);
  int klass = 0;
  if (teach != nullptr || expert_drives) {
    // A privileged expert sees the simulator's people where the tracker's would be (Demonstrations::people).
    const bool privileged = teach != nullptr && teach->people;
    const Surroundings truth = privileged ? Surroundings{teach->people(), seen.static_points} : Surroundings{};
    const Surroundings& expert_sees = privileged ? truth : seen;
    const int label = SafeDirectionLabel(
        robot, MoversAround(robot.translation(), expert_sees, options_.takiguchi.range_m, options_.takiguchi), bearing,
        options_.takiguchi, options_.safe);
    if (teach != nullptr) {
      teach->inputs.insert(teach->inputs.end(), input.data(), input.data() + input.size());
      for (int k = 0; k < TakiguchiClasses(options_.takiguchi); ++k) teach->targets.push_back(k == label ? 1.0F : 0.0F);
    }
    klass = label;
  }
  if (!expert_drives) {
    options_.direction->Forward(input).maxCoeff(&klass);
    step.learned = true;
  }
  Twist2 command = TakiguchiCommand(klass, options_.takiguchi);
  command.linear_mps = std::min({command.linear_mps, v_free, follow.speed_limit_mps});
  return command;
}

Twist2 LocalNavigator::Fuzzy(const Pose2& robot, const std::vector<LaneResult>& lanes, const FollowStep& follow,
                             double v_free, LocalStep& step) {
  // The cones ahead, in the robot's frame: front within 15 degrees of its heading, left and right out to 60; the free
  // distance in each to the nearest dead-end a lane saw or point the memory holds, from the footprint's edge.
  constexpr double kFrontRad = 15.0 * std::numbers::pi / 180.0;
  constexpr double kSideRad = 60.0 * std::numbers::pi / 180.0;
  FlmcInput in;
  in.left_m = in.front_m = in.right_m = std::numeric_limits<double>::infinity();
  const auto add = [&](const Eigen::Vector2d& p) {
    const double bearing = std::atan2(p.y(), p.x());
    if (std::abs(bearing) > kSideRad) return;
    const double distance = std::max(0.0, p.norm() - options_.memory.robot_radius_m);
    double& cone = std::abs(bearing) <= kFrontRad ? in.front_m : bearing > 0.0 ? in.left_m : in.right_m;
    cone = std::min(cone, distance);
  };
  for (const LaneResult& lane : lanes) {
    if (lane.dead_end && !lane.blind && !OnMap(robot, lane)) add(lane.point.head<2>());
  }
  const Pose2 robot_from_world = robot.Inverse();
  for (const Eigen::Vector2d& p : memory_.Points()) add(robot_from_world.Transform(p));
  const Eigen::Vector2d to_target = follow.target - robot.translation();
  in.bearing_rad = WrapAngle(std::atan2(to_target.y(), to_target.x()) - robot.yaw_rad);
  in.distance_m = follow.remaining_m;
  const FlmcOutput fuzzy = flmc_->Step(in);
  step.avoiding = fuzzy.mode == FlmcMode::kAvoidance;
  Twist2 command = fuzzy.twist;
  command.linear_mps = std::min({command.linear_mps, v_free, follow.speed_limit_mps});
  return command;
}

Twist2 LocalNavigator::Imitate(const Pose2& robot, const std::vector<LaneResult>& lanes, const FollowStep& follow,
                               const Twist2& expert, double v_free, LocalStep& step) {
  // What MORP-RB sees: the map's own obstacles are the path's business.
  seen_ = lanes;
  for (LaneResult& lane : seen_) {
    if (lane.dead_end && OnMap(robot, lane)) lane.dead_end = false;
  }
  const Eigen::Vector2d to_target = follow.target - robot.translation();
  features_.Push(seen_, std::atan2(to_target.y(), to_target.x()) - robot.yaw_rad, to_target.norm(),
                 follow.final_approach, last_command_);
  // The last stretch to a waypoint is the pose controller's (within a centimetre and a degree): the network drives
  // round what is in the way, it does not stop on a point. Nothing to learn there either.
  if (follow.final_approach) return expert;
  const Eigen::VectorXf input = features_.Input();
  Demonstrations* teach = options_.teach.get();
  if (teach != nullptr) {
    teach->inputs.insert(teach->inputs.end(), input.data(), input.data() + input.size());
    // On the network's scale, within what it can answer.
    teach->targets.push_back(static_cast<float>(std::clamp(expert.linear_mps / options_.il.max_linear_mps, -1.0, 1.0)));
    teach->targets.push_back(
        static_cast<float>(std::clamp(expert.angular_rps / options_.il.max_angular_rps, -1.0, 1.0)));
  }
  const bool expert_drives = !options_.learned || (teach != nullptr && std::uniform_real_distribution<double>(
                                                                           0.0, 1.0)(teach->random) < teach->beta);
  if (expert_drives) return expert;
  Twist2 learned = MorpIlCommand(*options_.learned, input, options_.il);
  learned.linear_mps = std::min({learned.linear_mps, v_free, follow.speed_limit_mps});
  step.learned = true;
  return learned;
}

bool LocalNavigator::OnMap(const Pose2& robot, const LaneResult& lane) const {
  const Costmap* map = memory_.map();  // the path's map
  if (map == nullptr) return false;
  const auto near_map_obstacle = [&](double x, double y) {
    return map->ClearanceAt(robot.Transform(Eigen::Vector2d(x, y))) <= options_.mapped_tolerance_m;
  };
  if (!lane.blind) return near_map_obstacle(lane.point.x(), lane.point.y());
  const double step = map->grid().resolution_m();
  for (double x = 0.0; x <= options_.blind_mapped_m; x += step) {
    if (near_map_obstacle(x, lane.offset_m)) return true;
  }
  return false;
}

void LocalNavigator::Evade(const Pose2& robot, const Eigen::Vector2d& target, const Surroundings* around,
                           LocalStep& step) {
  if (around == nullptr) return;
  const EvasionResult evasion =
      evade_.Check(robot, step.twist, target, around->objects, around->static_points, &memory_);
  step.evading = evasion.evading;
  step.twist = evasion.twist;
}

}  // namespace corridor::nav
