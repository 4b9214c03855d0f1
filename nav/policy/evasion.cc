#include "nav/policy/evasion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace

Evasion::Evasion(const EvasionOptions& options) : options_(options) {
  if (!(options.horizon_s > 0.0) || !(options.step_s > 0.0) || options.step_s > options.horizon_s) {
    throw std::invalid_argument("evasion: need 0 < step_s <= horizon_s");
  }
  if (options.static_horizon_s < 0.0 || options.static_horizon_s > options.horizon_s) {
    throw std::invalid_argument("evasion: static_horizon_s must be within [0, horizon_s]");
  }
  if (!(options.max_linear_mps > 0.0) || options.max_reverse_mps < 0.0 || !(options.max_turn_rps > 0.0)) {
    throw std::invalid_argument("evasion: speeds must be positive");
  }
}

Eigen::Vector2d Evasion::At(const Pose2& robot, const Manoeuvre& m, double t) const {
  const double turn_s = std::abs(m.turn_rad) / options_.max_turn_rps;
  if (t <= turn_s) return robot.translation();
  const Pose2 turned{robot.x_m, robot.y_m, robot.yaw_rad + m.turn_rad};
  return DriveArc(turned, m.drive, t - turn_s).translation();
}

Twist2 Evasion::FirstTwist(const Manoeuvre& m) const {
  if (m.turn_rad == 0.0) return m.drive;
  return {0.0, m.turn_rad > 0.0 ? options_.max_turn_rps : -options_.max_turn_rps};
}

Evasion::Score Evasion::Predict(const Pose2& robot, const Manoeuvre& m, const std::vector<Mover>& movers) const {
  Score score{kInfinity, kInfinity};
  std::vector<double> previous(movers.size());
  for (std::size_t i = 0; i < movers.size(); ++i) {
    previous[i] = (movers[i].position - robot.translation()).norm() - movers[i].clearance_m;
    score.closest_m = std::min(score.closest_m, previous[i]);
  }
  const int steps = static_cast<int>(std::round(options_.horizon_s / options_.step_s));
  for (int k = 1; k <= steps; ++k) {
    const double t = k * options_.step_s;
    const Eigen::Vector2d at = At(robot, m, t);
    for (std::size_t i = 0; i < movers.size(); ++i) {
      const double gap = (movers[i].position + t * movers[i].velocity - at).norm() - movers[i].clearance_m -
                         options_.uncertainty_mps * t;
      // Overlapping and still closing in; overlapping while separating is how the robot gets out.
      if (gap < 0.0 && gap < previous[i] - 1e-6) score.conflict_s = std::min(score.conflict_s, t);
      score.closest_m = std::min(score.closest_m, gap);
      previous[i] = gap;
    }
  }
  return score;
}

bool Evasion::StaticBlocked(const Pose2& robot, const Manoeuvre& m, const std::vector<Eigen::Vector2d>& near,
                            const ObstacleMemory* memory) const {
  if (memory != nullptr && memory->Blocks({robot.x_m, robot.y_m, robot.yaw_rad + m.turn_rad}, m.drive)) return true;
  const double clearance = options_.robot_radius_m + options_.static_margin_m;
  double now = kInfinity;
  for (const Eigen::Vector2d& p : near) now = std::min(now, (p - robot.translation()).norm());
  const int steps = static_cast<int>(std::round(options_.static_horizon_s / options_.step_s));
  for (int k = 1; k <= steps; ++k) {
    const Eigen::Vector2d at = At(robot, m, k * options_.step_s);
    for (const Eigen::Vector2d& p : near) {
      const double d = (p - at).norm();
      if (d < clearance && d < now - 1e-6) return true;
    }
  }
  return false;
}

EvasionResult Evasion::Check(const Pose2& robot, const Twist2& command, const std::vector<TrackedObject>& objects,
                             const std::vector<Eigen::Vector2d>& static_points, const ObstacleMemory* memory) const {
  const EvasionOptions& o = options_;
  std::vector<Mover> movers;
  for (const TrackedObject& object : objects) {
    if (!object.moving) continue;
    const double radius = std::max(object.radius_m, o.min_object_radius_m);
    const Eigen::Vector2d away = object.position - robot.translation();
    const Eigen::Vector2d centre =
        object.position + (away.norm() > 1e-6 ? away.normalized() : Eigen::Vector2d::Zero()) * o.far_side_fraction * radius;
    movers.push_back({centre, object.velocity, o.robot_radius_m + radius + o.margin_m});
  }
  EvasionResult result{command, false, kInfinity};
  if (movers.empty()) return result;
  const Score nominal = Predict(robot, {0.0, command}, movers);
  if (nominal.conflict_s == kInfinity) return result;

  std::vector<Eigen::Vector2d> near;
  for (const Eigen::Vector2d& p : static_points) {
    if ((p - robot.translation()).norm() <= o.static_reach_m) near.push_back(p);
  }
  std::vector<Manoeuvre> candidates;
  const double w = o.max_turn_rps;
  for (const double v : {o.max_linear_mps, 0.5 * o.max_linear_mps, 0.0, -0.5 * o.max_reverse_mps, -o.max_reverse_mps}) {
    for (const double turn : {0.0, 0.35 * w, -0.35 * w, 0.7 * w, -0.7 * w, w, -w}) candidates.push_back({0.0, {v, turn}});
  }
  for (const double turn : {std::numbers::pi / 4.0, -std::numbers::pi / 4.0, std::numbers::pi / 2.0, -std::numbers::pi / 2.0}) {
    for (const double v : {o.max_linear_mps, -o.max_reverse_mps}) candidates.push_back({turn, {v, 0.0}});
  }
  // Keeping the speed matters more than keeping the turn, as in the obstacle memory's guard.
  const auto cost = [&](const Twist2& t) {
    return 2.0 * std::abs(t.linear_mps - command.linear_mps) + std::abs(t.angular_rps - command.angular_rps);
  };
  bool found_clear = false;
  Manoeuvre best;  // standing still, unless something better is found
  Score best_score = Predict(robot, best, movers);
  for (const Manoeuvre& candidate : candidates) {
    if (candidate.drive.linear_mps != 0.0 && StaticBlocked(robot, candidate, near, memory)) continue;
    const Score score = Predict(robot, candidate, movers);
    if (score.conflict_s == kInfinity) {
      if (!found_clear || cost(FirstTwist(candidate)) < cost(FirstTwist(best))) {
        best = candidate;
        best_score = score;
      }
      found_clear = true;
    } else if (!found_clear &&
               (score.closest_m > best_score.closest_m + 1e-6 ||
                (score.closest_m > best_score.closest_m - 1e-6 && score.conflict_s > best_score.conflict_s))) {
      best = candidate;
      best_score = score;
    }
  }
  return {FirstTwist(best), true, best_score.conflict_s};
}

}  // namespace corridor::nav
