#include "nav/safety/obstacle_memory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace corridor::nav {
namespace {

constexpr double kMapQuantumM = 0.03;
// Closing in on a remembered point by less than this over the whole sweep is not driving into it: a robot creeping
// a few millimetres while it turns on the spot (the final approach, a centimetre from its goal) would otherwise have
// every turn refused while anything lies within the margin, and dither or spin in place until the point is forgotten.
constexpr double kCreepM = 0.005;

}  // namespace

void ObstacleMemory::Update(const Pose2& robot, const std::vector<LaneResult>& lanes, double dt_s) {
  const ObstacleMemoryOptions& o = options_;
  for (Point& p : points_) p.age_s += std::max(0.0, dt_s);
  std::erase_if(points_, [&](const Point& p) {
    return p.age_s > o.keep_s || (p.world - robot.translation()).norm() > o.keep_radius_m;
  });
  // Free floor seen past a remembered point clears it: the lanes clear what the lanes (or the bumper) put there, and
  // leave the depth scan's points to later scans (See). A lane looks down a line a centimetre or two wide, not its
  // whole width: a scan point on the slanted face of an obstacle, or on a cylinder's side beside the line, lies
  // within the lane's width and nearer than where the line meets the obstacle, and was never in what the lane saw.
  const Pose2 robot_inverse = robot.Inverse();
  std::erase_if(points_, [&](const Point& p) {
    if (p.scanned) return false;
    const Eigen::Vector2d local = robot_inverse.Transform(p.world);
    if (local.x() < o.clear_from_m) return false;
    return std::any_of(lanes.begin(), lanes.end(), [&](const LaneResult& lane) {
      return !lane.blind && std::abs(local.y() - lane.offset_m) <= o.lane_half_width_m &&
             local.x() < lane.free_distance_m - o.cell_m;
    });
  });
  for (const LaneResult& lane : lanes) {
    if (!lane.dead_end || lane.blind) continue;
    const Eigen::Vector2d world = robot.Transform(Eigen::Vector2d(lane.point.x(), lane.point.y()));
    // The map's own obstacles are known without it (as in See).
    if ((world - robot.translation()).norm() > o.keep_radius_m || OnMapWall(world)) continue;
    Remember(world);
  }
}

void ObstacleMemory::See(const Pose2& robot, const std::vector<Eigen::Vector2d>& scan, const SensorView& view) {
  const ObstacleMemoryOptions& o = options_;
  // The scan's nearest range from the camera in each bearing bin across the view; an empty bin saw nothing.
  const double bin_rad = o.scan_bearing_rad;
  const int bins = std::max(1, static_cast<int>(std::ceil(2.0 * view.half_angle_rad / bin_rad)));
  const auto bin_of = [&](const Eigen::Vector2d& in_view) {
    return static_cast<int>(std::floor((std::atan2(in_view.y(), in_view.x()) + view.half_angle_rad) / bin_rad));
  };
  std::vector<double> nearest(static_cast<std::size_t>(bins), std::numeric_limits<double>::infinity());
  const Pose2 view_T_base = view.world_T_sensor.Inverse();
  for (const Eigen::Vector2d& p : scan) {
    const Eigen::Vector2d in_view = view_T_base.Transform(p);
    const int b = bin_of(in_view);
    if (b >= 0 && b < bins) nearest[b] = std::min(nearest[b], in_view.norm());
  }
  // Seen past: forgotten. Not nearer than clear_from_m (below the image's bottom edge) and not in the outermost
  // bins (partly out of view).
  const Pose2 view_T_world = (robot * view.world_T_sensor).Inverse();
  std::erase_if(points_, [&](const Point& p) {
    if (!p.scanned) return false;
    const Eigen::Vector2d in_view = view_T_world.Transform(p.world);
    const double range = in_view.norm();
    if (range < o.clear_from_m || range > view.range_m) return false;
    const int b = bin_of(in_view);
    return b > 0 && b < bins - 1 && nearest[b] > range + o.scan_clear_m;
  });
  // Neighbouring columns a cell apart or less are one point; the map's own obstacles are known without it.
  const Eigen::Vector2d* last = nullptr;
  for (const Eigen::Vector2d& p : scan) {
    if (last != nullptr && (p - *last).norm() < o.cell_m) continue;
    last = &p;
    const Eigen::Vector2d world = robot.Transform(p);
    if ((world - robot.translation()).norm() > o.keep_radius_m) continue;
    if (OnMapWall(world)) continue;
    Remember(world, true);
  }
}

void ObstacleMemory::Remember(const Eigen::Vector2d& world, bool scanned) {
  const auto near = std::find_if(points_.begin(), points_.end(),
                                 [&](const Point& p) { return (p.world - world).norm() < options_.cell_m; });
  if (near != points_.end()) {
    *near = {world, 0.0, scanned};
  } else {
    points_.push_back({world, 0.0, scanned});
  }
}

void ObstacleMemory::Touched(const Pose2& robot, bool backing) {
  // Across the front (or back) half of the round footprint, just outside it: a bumper says "in front", not where.
  const double r = (backing ? -1.0 : 1.0) * (options_.robot_radius_m + 0.02);
  for (const double bearing : {-0.8, -0.4, 0.0, 0.4, 0.8}) {
    Remember(robot.Transform(Eigen::Vector2d(r * std::cos(bearing), r * std::sin(bearing))));
  }
}

bool ObstacleMemory::OnMapWall(const Eigen::Vector2d& at) const {
  return map_ && map_->WallWithin(at, options_.scan_map_tolerance_m, /*mapped_only=*/true);
}

double ObstacleMemory::MapClearance(const Eigen::Vector2d& at) const {
  return map_ ? map_->ClearanceAt(at) : std::numeric_limits<double>::infinity();
}

std::vector<Eigen::Vector2d> ObstacleMemory::Points() const {
  std::vector<Eigen::Vector2d> out;
  out.reserve(points_.size());
  for (const Point& p : points_) out.push_back(p.world);
  return out;
}

void ObstacleMemory::Forget(const Eigen::Vector2d& centre, double radius_m) {
  std::erase_if(points_, [&](const Point& p) { return (p.world - centre).norm() <= radius_m; });
}

ObstacleMemory::Blocker ObstacleMemory::BlockedBy(const Pose2& robot, const Twist2& command, bool approach) const {
  const ObstacleMemoryOptions& o = options_;
  const double map_clearance = o.robot_radius_m + o.map_margin_m;
  const double map_now = MapClearance(robot.translation());
  // Crossing the band (at a crawl: the planner caps the speed there), what the camera saw is kept at the final
  // approach's margin: the way out of a ring of specks passes closer than margin_m to some of them.
  // Near the crossing, and near enough the band to come into it within the margin: farther from the band the robot
  // is among what the camera saw alone, and keeps the full margin from it.
  const bool in_band =
      map_now < map_clearance || (band_from_ && (robot.translation() - *band_from_).norm() <= kEscapeReachM &&
                                  map_now < map_clearance + o.margin_m);
  const double clearance = o.robot_radius_m + (approach || in_band ? o.approach_margin_m : o.margin_m);
  // The footprint touches a wall cell (a square) up to half its diagonal nearer than the cell's centre.
  const double wall_contact_m = map_ ? o.robot_radius_m + 0.75 * map_->grid().resolution_m() : 0.0;
  double now = std::numeric_limits<double>::infinity();
  for (const Point& p : points_) now = std::min(now, (p.world - robot.translation()).norm());
  // The points within beside_m of touching (not on a final approach; in the band too, where the margin is the final
  // approach's), each with its distance now: none may come nearer than it is, and moving (more than creeping over the
  // horizon) must end farther from each.
  std::vector<std::pair<Eigen::Vector2d, double>> beside;
  if (!approach && now < o.robot_radius_m + o.beside_m) {
    for (const Point& p : points_) {
      const double from = (p.world - robot.translation()).norm();
      if (from < o.robot_radius_m + o.beside_m) beside.emplace_back(p.world, from);
    }
  }
  const bool moving = std::abs(command.linear_mps) * o.horizon_s > 2.0 * kCreepM;
  Blocker blocker = Blocker::kNone;
  for (double t = o.sweep_step_s; t <= o.horizon_s + 1e-9; t += o.sweep_step_s) {
    const Eigen::Vector2d at = DriveArc(robot, command, t).translation();
    // Closing in on the map's obstacles by more than the field's steps between neighbouring cells (driving along a
    // wall is not closing in).
    const double to_map = MapClearance(at);
    if (!in_band) {
      if (to_map < map_clearance && to_map < map_now - kMapQuantumM) blocker = Blocker::kMap;
    } else if (map_->WallWithin(at, wall_contact_m) && !map_->WallWithin(robot.translation(), wall_contact_m)) {
      blocker = Blocker::kMap;
    }
    for (const Point& p : points_) {
      const double d = (p.world - at).norm();
      // Inside the clearance and closing in: blocked. Already inside and moving away is how the robot gets out.
      if (d < clearance && d < now - kCreepM) return Blocker::kSeen;
    }
    const bool last = t + o.sweep_step_s > o.horizon_s + 1e-9;
    for (const auto& [point, from] : beside) {
      const double d = (point - at).norm();
      if (d < from - kCreepM || (last && moving && d <= from + kCreepM)) return Blocker::kSeen;
    }
  }
  return blocker;
}

Twist2 ObstacleMemory::Guard(const Pose2& robot, const Twist2& command, bool approach, Blocker* refused_by) const {
  const Blocker blocker = points_.empty() && !map_ ? Blocker::kNone : BlockedBy(robot, command, approach);
  if (refused_by != nullptr) *refused_by = blocker;
  if (blocker == Blocker::kNone) return command;
  // Keeping the speed matters more than keeping the turn: a robot that bends away keeps going.
  const auto cost = [&](const Twist2& t) {
    return 2.0 * std::abs(t.linear_mps - command.linear_mps) + std::abs(t.angular_rps - command.angular_rps);
  };
  const double w_max = options_.max_turn_rps;
  std::optional<Twist2> best;
  for (const double v : {command.linear_mps, 0.5 * command.linear_mps}) {
    if (v == 0.0) continue;
    for (const double dw : {0.0, 0.25, -0.25, 0.5, -0.5, 0.75, -0.75, 1.0, -1.0, 1.5, -1.5, 2.0, -2.0}) {
      const Twist2 candidate{v, std::clamp(command.angular_rps + dw, -w_max, w_max)};
      if ((!best || cost(candidate) < cost(*best)) && !Blocks(robot, candidate, approach)) best = candidate;
    }
  }
  if (best) return *best;
  // Refused by the map alone, a turning command turns on the spot the way it was turning: the robot comes to face
  // where it is going and the next arc is straighter. (Turning away from the map's nearer side instead fought the
  // follower's own turn beside a corner of the map, each undoing the other for as long as the mission lasted.)
  const double w_spot = 0.7 * w_max;
  if (blocker == Blocker::kMap && command.angular_rps != 0.0) return {0.0, std::copysign(w_spot, command.angular_rps)};
  // Turn away from the nearest remembered point, or else from the map's nearer side.
  double side = 0.0;  // > 0: it is on the left
  if (!points_.empty()) {
    const auto nearest = std::min_element(points_.begin(), points_.end(), [&](const Point& a, const Point& b) {
      return (a.world - robot.translation()).squaredNorm() < (b.world - robot.translation()).squaredNorm();
    });
    side = robot.Inverse().Transform(nearest->world).y();
  } else {
    const double aside = options_.robot_radius_m;
    side = MapClearance(robot.Transform(Eigen::Vector2d(0.0, -aside))) -
           MapClearance(robot.Transform(Eigen::Vector2d(0.0, aside)));
  }
  return {0.0, side > 0.0 ? -w_spot : w_spot};
}

}  // namespace corridor::nav
