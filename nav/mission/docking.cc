#include "nav/mission/docking.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace corridor::nav {
namespace {

constexpr double kHeadingSpan = 0.35;  // headings searched either side of the expected one (20 degrees)
constexpr double kHeadingStep = 0.0125;
constexpr double kBand = 0.02;     // a line's points lie within this band
constexpr double kInlier = 0.015;  // after the fit
constexpr double kMaxGap = 0.05;   // a face is one run of points with no wider gap
constexpr std::size_t kMinPoints = 8;
constexpr double kSightingWeight = 0.3;

Eigen::Vector2d Heading(double yaw) { return {std::cos(yaw), std::sin(yaw)}; }

// The densest band of width kBand across `points` projected on `normal`: how many lie in it and its mean offset;
// on a tie the nearer band (the dock stands in front of the wall behind it).
std::pair<std::size_t, double> DensestBand(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& normal,
                                           std::vector<double>& offsets) {
  offsets.clear();
  for (const Eigen::Vector2d& p : points) offsets.push_back(p.dot(normal));
  std::sort(offsets.begin(), offsets.end());
  std::size_t best = 0;
  double best_offset = 0.0;
  double sum = 0.0;
  std::size_t lo = 0;
  for (std::size_t hi = 0; hi < offsets.size(); ++hi) {
    sum += offsets[hi];
    while (offsets[hi] - offsets[lo] > kBand) sum -= offsets[lo++];
    const std::size_t count = hi - lo + 1;
    if (count > best) {
      best = count;
      best_offset = sum / static_cast<double>(count);
    }
  }
  return {best, best_offset};
}

}  // namespace

Pose2 StagingPose(const Pose2& docked, const DockGeometry& dock) {
  return docked * Pose2{-dock.staging_distance_m, 0.0, 0.0};
}

std::optional<std::string> DockUnreachable(const Costmap& costmap, const Pose2& docked, const DockGeometry& dock) {
  const Pose2 staging = StagingPose(docked, dock);
  std::ostringstream why;
  why << std::fixed << std::setprecision(2) << "its staging pose (" << staging.x_m << ", " << staging.y_m << "), "
      << dock.staging_distance_m << " m straight back from the docked pose,";
  const auto cell = costmap.grid().WorldToCell(staging.translation());
  if (!cell) {
    why << " is outside the map";
    return why.str();
  }
  const std::size_t i = costmap.Index(*cell);
  if (costmap.Traversable(i)) return std::nullopt;
  if (costmap.InKeepOut(i)) {
    why << " is in a keep-out zone";
  } else if (costmap.IsObstacle(i)) {
    why << " is on an obstacle or unknown space";
  } else {
    why << " is " << costmap.clearance_m(i) << " m from an obstacle; the robot needs "
        << costmap.options().robot_radius_m << " m and half a cell";
  }
  return why.str();
}

MissionGoal DockGoal(const Place& dock, const DockGeometry& geometry) {
  MissionGoal goal;
  goal.pose = StagingPose(dock.pose, geometry);
  goal.has_yaw = true;
  goal.place = dock.name;
  goal.action = GoalAction::kDock;
  goal.dock = dock.pose;
  return goal;
}

MissionGoal UndockGoal(const std::optional<Pose2>& robot, const DockGeometry& geometry) {
  MissionGoal goal;
  goal.action = GoalAction::kUndock;
  if (robot) {
    goal.pose = StagingPose(*robot, geometry);
    goal.has_yaw = true;
  }
  return goal;
}

std::optional<Place> NearestDock(const std::vector<Place>& places, const Eigen::Vector2d& robot) {
  std::optional<Place> best;
  for (const Place& p : places) {
    if (p.kind != PlaceKind::kDock) continue;
    if (!best || (p.pose.translation() - robot).norm() < (best->pose.translation() - robot).norm()) best = p;
  }
  return best;
}

void Validate(const DockingOptions& o) {
  ValidateGains(o.gains);
  const auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(what) + " must be positive");
  };
  positive(o.dock.width_m, "dock width");
  positive(o.dock.face_distance_m, "dock face distance");
  positive(o.max_speed_mps, "docking max speed");
  if (!(o.min_speed_mps >= 0.0 && o.min_speed_mps < o.max_speed_mps)) {
    throw std::invalid_argument("docking min speed must be between 0 and the max speed");
  }
  positive(o.max_turn_rps, "docking max turn rate");
  positive(o.position_tolerance_m, "docking position tolerance");
  positive(o.yaw_tolerance_rad, "docking yaw tolerance");
  positive(o.search_window_m, "docking search window");
  positive(o.width_tolerance_m, "docking width tolerance");
  positive(o.not_seen_s, "docking not_seen_s");
  positive(o.timeout_s, "docking timeout");
  positive(o.undock_tolerance_m, "undocking tolerance");
  if (!(o.dock.staging_distance_m > o.blind_distance_m - o.dock.face_distance_m)) {
    throw std::invalid_argument("the staging distance must put the robot farther from the dock than blind_distance_m");
  }
  if (!(o.blind_distance_m > o.dock.face_distance_m)) {
    throw std::invalid_argument("blind_distance_m must exceed the dock's face distance");
  }
  if (o.min_sightings < 1) throw std::invalid_argument("docking min_sightings must be at least 1");
}

std::optional<Pose2> FindDockFace(const std::vector<Eigen::Vector2d>& scan, const Pose2& expected,
                                  const DockingOptions& o) {
  const double half_width = o.dock.width_m / 2.0;
  const Eigen::Vector2d n0 = Heading(expected.yaw_rad);
  const Eigen::Vector2d t0(-n0.y(), n0.x());
  const Eigen::Vector2d face0 = expected.translation() + n0 * o.dock.face_distance_m;
  std::vector<Eigen::Vector2d> near;
  for (const Eigen::Vector2d& p : scan) {
    const Eigen::Vector2d d = p - face0;
    if (std::abs(d.dot(t0)) <= half_width + o.search_window_m && std::abs(d.dot(n0)) <= o.search_window_m) {
      near.push_back(p);
    }
  }
  if (near.size() < kMinPoints) return std::nullopt;

  // The line: the heading (near the expected one) and offset whose band holds the most points.
  std::vector<double> offsets;
  std::size_t best = 0;
  double best_yaw = expected.yaw_rad;
  double best_offset = 0.0;
  for (double a = -kHeadingSpan; a <= kHeadingSpan + 1e-9; a += kHeadingStep) {
    const auto [count, offset] = DensestBand(near, Heading(expected.yaw_rad + a), offsets);
    if (count > best || (count == best && offset < best_offset)) {
      best = count;
      best_yaw = expected.yaw_rad + a;
      best_offset = offset;
    }
  }
  if (best < kMinPoints) return std::nullopt;

  // Refined by a least-squares fit to the band's points.
  std::vector<Eigen::Vector2d> inliers;
  const Eigen::Vector2d n1 = Heading(best_yaw);
  for (const Eigen::Vector2d& p : near) {
    if (std::abs(p.dot(n1) - best_offset) <= kBand) inliers.push_back(p);
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : inliers) mean += p;
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : inliers) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov);
  Eigen::Vector2d normal = solver.eigenvectors().col(0);  // the smallest spread: across the line
  if (normal.dot(n1) < 0.0) normal = -normal;             // into the dock, as the expected heading
  const Eigen::Vector2d tangent(-normal.y(), normal.x());

  // The face: the widest run of the line's points without a gap, which must be about the dock's width.
  std::vector<double> along;
  for (const Eigen::Vector2d& p : near) {
    if (std::abs((p - mean).dot(normal)) <= kInlier) along.push_back((p - mean).dot(tangent));
  }
  if (along.size() < kMinPoints) return std::nullopt;
  std::sort(along.begin(), along.end());
  double run_lo = along.front();
  double widest_lo = 0.0;
  double widest_hi = -1.0;
  for (std::size_t i = 0; i < along.size(); ++i) {
    if (i > 0 && along[i] - along[i - 1] > kMaxGap) run_lo = along[i];
    if (along[i] - run_lo > widest_hi - widest_lo) {
      widest_lo = run_lo;
      widest_hi = along[i];
    }
  }
  if (std::abs((widest_hi - widest_lo) - o.dock.width_m) > o.width_tolerance_m) return std::nullopt;
  const Eigen::Vector2d centre = mean + tangent * (widest_lo + widest_hi) / 2.0;
  const Eigen::Vector2d docked = centre - normal * o.dock.face_distance_m;
  return Pose2{docked.x(), docked.y(), std::atan2(normal.y(), normal.x())};
}

const char* ToString(DockingPhase phase) {
  switch (phase) {
    case DockingPhase::kSeeking: return "seeking";
    case DockingPhase::kApproaching: return "approaching";
    case DockingPhase::kFinal: return "final";
    case DockingPhase::kDocked: return "docked";
    case DockingPhase::kUndocking: return "undocking";
    case DockingPhase::kUndocked: return "undocked";
    case DockingPhase::kFailed: return "failed";
  }
  return "unknown";
}

Docking::Docking(const DockingOptions& options, const Pose2& target, DockingPhase phase, double now_s)
    : options_(options), target_(target), phase_(phase), started_s_(now_s) {
  Validate(options);
}

Docking Docking::Dock(const DockingOptions& options, const Pose2& odom_T_dock, double now_s) {
  return Docking(options, odom_T_dock, DockingPhase::kSeeking, now_s);
}

Docking Docking::Undock(const DockingOptions& options, const Pose2& odom_T_base, double now_s) {
  return Docking(options, StagingPose(odom_T_base, options.dock), DockingPhase::kUndocking, now_s);
}

void Docking::Sighted(const Pose2& odom_T_dock) {
  // An exponential mean: a sighting's error grows with the odometry's drift since it was made, so the newest (and
  // nearest) weigh most; the first replaces the map's guess.
  const double weight = sightings_ == 0 ? 1.0 : kSightingWeight;
  ++sightings_;
  const Pose2 change = target_.Inverse() * odom_T_dock;
  target_ = target_ * Pose2{weight * change.x_m, weight * change.y_m, weight * change.yaw_rad};
}

DockingStep Docking::Drive(const Pose2& odom_T_base, double tolerance_m, bool turn_to_heading) {
  DockingStep step;
  const PolarCommand c = PolarControl(odom_T_base, target_, options_.gains, true);
  step.remaining_m = c.rho;
  if (c.rho <= tolerance_m) {
    const double yaw_error = WrapAngle(target_.yaw_rad - odom_T_base.yaw_rad);
    if (!turn_to_heading || std::abs(yaw_error) <= options_.yaw_tolerance_rad) {
      phase_ = phase_ == DockingPhase::kUndocking ? DockingPhase::kUndocked : DockingPhase::kDocked;
      step.phase = phase_;
      return step;
    }
    // In place: the last fraction of a degree.
    step.twist.angular_rps = std::clamp(1.5 * yaw_error, -options_.max_turn_rps, options_.max_turn_rps);
    step.phase = phase_;
    return step;
  }
  Twist2 t = c.twist;
  // Slowed as a whole, so that the controller's curvature (and its convergence) is kept.
  double scale = 1.0;
  if (std::abs(t.linear_mps) > options_.max_speed_mps) scale = options_.max_speed_mps / std::abs(t.linear_mps);
  if (std::abs(t.linear_mps) < options_.min_speed_mps && t.linear_mps != 0.0) {
    scale = options_.min_speed_mps / std::abs(t.linear_mps);
  }
  if (std::abs(t.angular_rps) * scale > options_.max_turn_rps) scale = options_.max_turn_rps / std::abs(t.angular_rps);
  step.twist = {t.linear_mps * scale, t.angular_rps * scale};
  step.phase = phase_;
  return step;
}

DockingStep Docking::Update(double now_s, const Pose2& odom_T_base, const std::vector<Eigen::Vector2d>* scan) {
  DockingStep step;
  if (phase_ == DockingPhase::kDocked || phase_ == DockingPhase::kUndocked || phase_ == DockingPhase::kFailed) {
    step.phase = phase_;
    return step;
  }
  const auto fail = [&](std::string why) {
    phase_ = DockingPhase::kFailed;
    step = {};
    step.phase = phase_;
    step.error = std::move(why);
    return step;
  };
  if (now_s - started_s_ > options_.timeout_s) {
    return fail(phase_ == DockingPhase::kUndocking ? "undocking did not finish in time"
                                                   : "docking did not finish in time");
  }
  if (phase_ == DockingPhase::kUndocking) return Drive(odom_T_base, options_.undock_tolerance_m, false);

  const Pose2 base_T_dock = odom_T_base.Inverse() * target_;
  const double face_m = base_T_dock.Transform({options_.dock.face_distance_m, 0.0}).norm();
  bool seen = false;
  if (phase_ != DockingPhase::kFinal && scan != nullptr && face_m > options_.blind_distance_m) {
    if (const auto found = FindDockFace(*scan, base_T_dock, options_)) {
      Sighted(odom_T_base * *found);
      seen = true;
    }
  }
  if (phase_ == DockingPhase::kSeeking) {
    if (sightings_ >= options_.min_sightings) {
      phase_ = DockingPhase::kApproaching;
    } else if (now_s - started_s_ > options_.not_seen_s) {
      return fail("the dock was not seen where the map puts it");
    } else {
      step.phase = phase_;
      step.seen = seen;
      step.remaining_m = base_T_dock.translation().norm();
      return step;
    }
  }
  if (phase_ == DockingPhase::kApproaching && face_m <= options_.blind_distance_m) phase_ = DockingPhase::kFinal;
  step = Drive(odom_T_base, options_.position_tolerance_m, true);
  step.seen = seen;
  return step;
}

bool ChargingPolicy::ShouldGo(double now_s, double charge, bool on_charger, bool busy) {
  if (options_.charge_below_percent <= 0.0 || on_charger || busy) return false;
  if (charge * 100.0 >= options_.charge_below_percent || now_s - last_s_ < options_.retry_s) return false;
  last_s_ = now_s;
  return true;
}

}  // namespace corridor::nav
