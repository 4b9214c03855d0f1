#include "nav/policy/evasion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace corridor::nav {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace

EvasionOptions ForForwardView(EvasionOptions options) {
  options.max_reverse_mps = 0.0;
  return options;
}

Evasion::Evasion(const EvasionOptions& options) : options_(options) {
  if (!(options.horizon_s > 0.0) || !(options.step_s > 0.0) || options.step_s > options.horizon_s) {
    throw std::invalid_argument("evasion: need 0 < step_s <= horizon_s");
  }
  if (options.static_horizon_s < 0.0 || options.static_horizon_s > options.horizon_s) {
    throw std::invalid_argument("evasion: static_horizon_s must be within [0, horizon_s]");
  }
  if (options.turn_reach_m < 0.0 || options.turn_horizon_s < 0.0 || options.walk_end_slack_m < 0.0) {
    throw std::invalid_argument("evasion: turn_reach_m, turn_horizon_s and walk_end_slack_m must not be negative");
  }
  if (options.first_s < 0.0 || options.first_s > options.horizon_s) {
    throw std::invalid_argument("evasion: first_s must be within [0, horizon_s]");
  }
  if (!(options.max_linear_mps > 0.0) || options.max_reverse_mps < 0.0 || !(options.max_turn_rps > 0.0)) {
    throw std::invalid_argument("evasion: speeds must be positive");
  }
  steps_ = static_cast<int>(std::round(options.horizon_s / options.step_s));
  first_steps_ = static_cast<int>(std::round(options.first_s / options.step_s));
  turn_steps_ = std::min(steps_, static_cast<int>(std::round(options.turn_horizon_s / options.step_s)));
  const double w = options.max_turn_rps;
  for (const double v : {options.max_linear_mps, 0.5 * options.max_linear_mps, 0.0, -0.5 * options.max_reverse_mps,
                         -options.max_reverse_mps}) {
    for (const double turn : {0.0, 0.5 * w, -0.5 * w, w, -w}) twists_.push_back({v, turn});
  }
  for (const Twist2& twist : twists_) chords_.push_back(Chord(twist));
}

std::vector<Eigen::Vector2d> Evasion::Chord(const Twist2& twist) const {
  std::vector<Eigen::Vector2d> chord(static_cast<std::size_t>(steps_));
  for (int j = 1; j <= steps_; ++j) chord[j - 1] = Arc(twist, j * options_.step_s).translation();
  return chord;
}

void Evasion::Trace(const Pose2& start, const std::vector<Eigen::Vector2d>& chord, int from_step,
                    std::vector<Eigen::Vector2d>& at) const {
  at.resize(static_cast<std::size_t>(steps_));
  const double c = std::cos(start.yaw_rad);
  const double s = std::sin(start.yaw_rad);
  for (int k = from_step + 1; k <= steps_; ++k) {
    const Eigen::Vector2d& p = chord[k - from_step - 1];
    at[k - 1] = {start.x_m + c * p.x() - s * p.y(), start.y_m + s * p.x() + c * p.y()};
  }
}

Evasion::Score Evasion::Predict(const std::vector<Eigen::Vector2d>& at, const std::vector<Mover>& movers,
                                const Paths& paths, int from_step, int to_step, Score score,
                                std::vector<double>& gaps) const {
  for (std::size_t i = 0; i < movers.size(); ++i) {
    const Mover& m = movers[i];
    const std::vector<Eigen::Vector2d>& path = paths[i];
    double previous = gaps[i];
    for (int k = from_step + 1, end = std::min(to_step, m.steps); k <= end; ++k) {
      const double t = k * options_.step_s;
      const double gap = (path[k - 1] - at[k - 1]).norm() - m.clearance_m - options_.uncertainty_mps * t;
      // Overlapping and still closing in; overlapping while separating is how the robot gets out.
      if (gap < 0.0 && gap < previous - 1e-6) score.conflict_s = std::min(score.conflict_s, t);
      score.closest_m = std::min(score.closest_m, gap);
      previous = gap;
    }
    gaps[i] = previous;
  }
  return score;
}

bool Evasion::StaticBlocked(const Pose2& robot, const std::vector<Eigen::Vector2d>& at, int steps,
                            const std::vector<Eigen::Vector2d>& near) const {
  const double clearance = options_.robot_radius_m + options_.static_margin_m;
  for (const Eigen::Vector2d& p : near) {
    double previous = (p - robot.translation()).norm();
    for (int k = 1; k <= steps; ++k) {
      const double d = (p - at[k - 1]).norm();
      if (d < clearance && d < previous - 1e-6) return true;
      previous = d;
    }
  }
  return false;
}

EvasionResult Evasion::Check(const Pose2& robot, const Twist2& command, const Eigen::Vector2d& target,
                             const std::vector<TrackedObject>& objects,
                             const std::vector<Eigen::Vector2d>& static_points, const ObstacleMemory* memory) {
  const EvasionOptions& o = options_;
  std::vector<Mover> movers;
  for (const TrackedObject& object : objects) {
    if (!object.moving) continue;
    const double radius = std::max(object.radius_m, o.min_object_radius_m);
    const Eigen::Vector2d away = object.position - robot.translation();
    const Eigen::Vector2d centre =
        object.position +
        (away.norm() > 1e-6 ? away.normalized() : Eigen::Vector2d::Zero()) * o.far_side_fraction * radius;
    const double clearance = o.robot_radius_m + radius + o.margin_m;
    const Eigen::Vector2d heading = object.velocity.normalized();  // zero stays zero: no turn predicted
    if (object.turn_at) {
      const double ahead = std::max(0.0, heading.dot(*object.turn_at - object.position) + o.walk_end_slack_m);
      movers.push_back({centre, object.velocity, clearance, steps_, ahead / object.velocity.norm()});
      continue;
    }
    movers.push_back({centre, object.velocity, clearance, steps_, kInfinity});
    // Walking away with the robot in their wake (on their line, behind them): should they turn round, they walk
    // straight into it.
    const double behind = heading.dot(away);
    const double aside = std::abs(heading.x() * away.y() - heading.y() * away.x());
    if (behind > 0.0 && aside < clearance && behind - clearance < o.turn_reach_m) {
      movers.push_back({centre, -object.velocity, clearance, turn_steps_, kInfinity});
    }
  }
  const std::optional<Twist2> last = std::exchange(last_, std::nullopt);
  EvasionResult result{command, false, kInfinity};
  if (movers.empty()) return result;
  Paths paths;
  std::vector<double> start_gaps;
  Score start{kInfinity, kInfinity};
  for (const Mover& m : movers) {
    std::vector<Eigen::Vector2d>& path = paths.emplace_back(static_cast<std::size_t>(m.steps));
    for (int k = 1; k <= m.steps; ++k) path[k - 1] = m.At(k * o.step_s);
    start_gaps.push_back((m.position - robot.translation()).norm() - m.clearance_m);
    start.closest_m = std::min(start.closest_m, start_gaps.back());
  }
  std::vector<Eigen::Vector2d> at;
  std::vector<double> gaps = start_gaps;
  Trace(robot, Chord(command), 0, at);
  if (Predict(at, movers, paths, 0, steps_, start, gaps).conflict_s == kInfinity) return result;

  std::vector<Eigen::Vector2d> near;
  for (const Eigen::Vector2d& p : static_points) {
    if ((p - robot.translation()).norm() <= o.static_reach_m) near.push_back(p);
  }
  const int static_steps = static_cast<int>(std::round(o.static_horizon_s / o.step_s));
  struct Candidate {
    std::size_t first;  // indices into twists_
    std::size_t then;
    double value;
    Score score;
  };
  std::vector<Candidate> clear;
  std::optional<Candidate> least_bad;
  const double distance_now = (target - robot.translation()).norm();
  std::vector<double> first_gaps;
  for (std::size_t f = 0; f < twists_.size(); ++f) {
    // The first part must keep clear of what stands still; the whole manoeuvre is checked once chosen. Only the
    // second part changes from one manoeuvre to the next, so the first part's prediction is made once.
    const Twist2& first = twists_[f];
    Trace(robot, chords_[f], 0, at);
    const bool moves = first.linear_mps != 0.0;
    if (moves &&
        ((memory != nullptr && memory->Blocks(robot, first)) || StaticBlocked(robot, at, static_steps, near))) {
      continue;
    }
    first_gaps = start_gaps;
    const Score first_score = Predict(at, movers, paths, 0, first_steps_, start, first_gaps);
    const Pose2 mid = DriveArc(robot, first, first_steps_ * o.step_s);
    const double leaving = o.smooth_weight * (std::abs(first.linear_mps - command.linear_mps) +
                                              std::abs(first.angular_rps - command.angular_rps) / 3.0);
    const double kept =
        last && last->linear_mps == first.linear_mps && last->angular_rps == first.angular_rps ? o.commit_bonus : 0.0;
    for (std::size_t t = 0; t < twists_.size(); ++t) {
      Trace(mid, chords_[t], first_steps_, at);
      gaps = first_gaps;
      const Score score = Predict(at, movers, paths, first_steps_, steps_, first_score, gaps);
      const double progress = distance_now - (target - at.back()).norm();
      const double value = progress - o.social_weight * std::max(0.0, o.social_m - score.closest_m) - leaving + kept;
      const Candidate candidate{f, t, value, score};
      if (score.conflict_s == kInfinity) {
        clear.push_back(candidate);
      } else if (!least_bad || score.closest_m > least_bad->score.closest_m + 1e-6 ||
                 (score.closest_m > least_bad->score.closest_m - 1e-6 &&
                  score.conflict_s > least_bad->score.conflict_s)) {
        least_bad = candidate;
      }
    }
  }
  std::sort(clear.begin(), clear.end(), [](const Candidate& a, const Candidate& b) { return a.value > b.value; });
  for (const Candidate& c : clear) {
    Trace(robot, chords_[c.first], 0, at);
    Trace(DriveArc(robot, twists_[c.first], first_steps_ * o.step_s), chords_[c.then], first_steps_, at);
    if (!StaticBlocked(robot, at, steps_, near)) {
      last_ = twists_[c.first];
      return {twists_[c.first], true, kInfinity};
    }
  }
  if (least_bad) {
    last_ = twists_[least_bad->first];
    return {twists_[least_bad->first], true, least_bad->score.conflict_s};
  }
  return {{0.0, 0.0}, true, 0.0};  // every way moves into something standing: stand still
}

}  // namespace corridor::nav
