#include "drivers/sim/crowd.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace corridor::drivers::sim {
namespace {

const Eigen::Vector3f kPersonColor(0.2f, 0.35f, 0.8f);
constexpr int kPrismSides = 16;
constexpr double kEpsilon = 1e-9;

double Det(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// ORCA's half-planes: velocities v with Det(direction, point - v) <= 0 are allowed (left of the directed line).
struct Line {
  Eigen::Vector2d point;
  Eigen::Vector2d direction;
};

// The ORCA half-plane for a pair: `relative_position` of the other, our velocity relative to its, combined radius.
// `share` is the part of the avoidance we take (0.5 reciprocal, 1 against a static obstacle).
Line OrcaLine(const Eigen::Vector2d& velocity, const Eigen::Vector2d& relative_position,
              const Eigen::Vector2d& relative_velocity, double radius, double horizon, double dt, double share) {
  const Eigen::Vector2d& p = relative_position;
  const Eigen::Vector2d& v = relative_velocity;
  const double dist2 = p.squaredNorm();
  const double r2 = radius * radius;
  Line line;
  Eigen::Vector2d u;
  if (dist2 > r2) {
    // Not in contact: the velocity obstacle is a cone truncated by a disc at p / horizon.
    const Eigen::Vector2d w = v - p / horizon;
    const double w_len2 = w.squaredNorm();
    const double along = w.dot(p);
    if (along < 0.0 && along * along > r2 * w_len2) {
      // Nearest to the truncating disc.
      const double w_len = std::sqrt(w_len2);
      const Eigen::Vector2d unit_w = w / w_len;
      line.direction = {unit_w.y(), -unit_w.x()};
      u = (radius / horizon - w_len) * unit_w;
    } else {
      // Nearest to one of the cone's legs.
      const double leg = std::sqrt(dist2 - r2);
      if (Det(p, w) > 0.0) {
        line.direction = Eigen::Vector2d(p.x() * leg - p.y() * radius, p.x() * radius + p.y() * leg) / dist2;
      } else {
        line.direction = -Eigen::Vector2d(p.x() * leg + p.y() * radius, -p.x() * radius + p.y() * leg) / dist2;
      }
      u = v.dot(line.direction) * line.direction - v;
    }
  } else {
    // Already overlapping: separate within this step.
    const Eigen::Vector2d w = v - p / dt;
    const double w_len = std::max(w.norm(), kEpsilon);
    const Eigen::Vector2d unit_w = w / w_len;
    line.direction = {unit_w.y(), -unit_w.x()};
    u = (radius / dt - w_len) * unit_w;
  }
  line.point = velocity + share * u;
  return line;
}

// The best velocity on line `index` within the speed disc and lines [0, index); false when there is none.
bool SolveOnLine(const std::vector<Line>& lines, std::size_t index, double radius, const Eigen::Vector2d& target,
                 bool direction_only, Eigen::Vector2d& result) {
  const Line& line = lines[index];
  const double along = line.point.dot(line.direction);
  const double discriminant = along * along + radius * radius - line.point.squaredNorm();
  if (discriminant < 0.0) return false;  // the line misses the speed disc
  const double root = std::sqrt(discriminant);
  double t_left = -along - root;
  double t_right = -along + root;
  for (std::size_t i = 0; i < index; ++i) {
    const double denominator = Det(line.direction, lines[i].direction);
    const double numerator = Det(lines[i].direction, line.point - lines[i].point);
    if (std::abs(denominator) <= kEpsilon) {
      if (numerator < 0.0) return false;  // parallel and outside
      continue;
    }
    const double t = numerator / denominator;
    if (denominator >= 0.0) {
      t_right = std::min(t_right, t);
    } else {
      t_left = std::max(t_left, t);
    }
    if (t_left > t_right) return false;
  }
  if (direction_only) {
    result = line.point + (target.dot(line.direction) > 0.0 ? t_right : t_left) * line.direction;
  } else {
    const double t = std::clamp(line.direction.dot(target - line.point), t_left, t_right);
    result = line.point + t * line.direction;
  }
  return true;
}

// The velocity nearest `target` (or furthest along it, direction_only) within all lines and the speed disc.
// Returns the index of the first line that made it infeasible, or lines.size().
std::size_t Solve(const std::vector<Line>& lines, double radius, const Eigen::Vector2d& target, bool direction_only,
                  Eigen::Vector2d& result) {
  if (direction_only) {
    result = target * radius;
  } else if (target.squaredNorm() > radius * radius) {
    result = target.normalized() * radius;
  } else {
    result = target;
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (Det(lines[i].direction, lines[i].point - result) > 0.0) {
      const Eigen::Vector2d previous = result;
      if (!SolveOnLine(lines, i, radius, target, direction_only, result)) {
        result = previous;
        return i;
      }
    }
  }
  return lines.size();
}

// Crowded beyond feasibility: the velocity that violates the lines from `first_failed` on the least.
void SolveLeastViolation(const std::vector<Line>& lines, std::size_t first_failed, double radius,
                         Eigen::Vector2d& result) {
  double distance = 0.0;
  for (std::size_t i = first_failed; i < lines.size(); ++i) {
    if (Det(lines[i].direction, lines[i].point - result) <= distance) continue;
    std::vector<Line> projected;
    for (std::size_t j = 0; j < i; ++j) {
      Line line;
      const double determinant = Det(lines[i].direction, lines[j].direction);
      if (std::abs(determinant) <= kEpsilon) {
        if (lines[i].direction.dot(lines[j].direction) > 0.0) continue;  // same direction
        line.point = 0.5 * (lines[i].point + lines[j].point);
      } else {
        line.point = lines[i].point +
                     (Det(lines[j].direction, lines[i].point - lines[j].point) / determinant) * lines[i].direction;
      }
      line.direction = (lines[j].direction - lines[i].direction).normalized();
      projected.push_back(line);
    }
    const Eigen::Vector2d previous = result;
    if (Solve(projected, radius, Eigen::Vector2d(-lines[i].direction.y(), lines[i].direction.x()), true, result) <
        projected.size()) {
      result = previous;  // numerical trouble: keep the last good one
    }
    distance = Det(lines[i].direction, lines[i].point - result);
  }
}

}  // namespace

Eigen::Vector2d OrcaVelocity(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity, double radius_m,
                             const Eigen::Vector2d& preferred, double max_speed, double time_horizon_s, double dt_s,
                             const std::vector<OrcaNeighbour>& neighbours) {
  std::vector<Line> lines;
  lines.reserve(neighbours.size());
  for (const OrcaNeighbour& n : neighbours) {
    lines.push_back(OrcaLine(velocity, n.position - position, velocity - n.velocity, radius_m + n.radius_m,
                             time_horizon_s, dt_s, n.reciprocal ? 0.5 : 1.0));
  }
  Eigen::Vector2d result;
  const std::size_t failed = Solve(lines, max_speed, preferred, false, result);
  if (failed < lines.size()) SolveLeastViolation(lines, failed, max_speed, result);
  return result;
}

Crowd::Crowd(const World& world, std::vector<PedestrianRoute> routes, const CrowdOptions& options)
    : collision_(world.collision), obstacles_(world.obstacles), options_(options) {
  for (const PedestrianRoute& route : routes) {
    Pedestrian p;
    p.position = route.start;
    p.route = route;
    pedestrians_.push_back(p);
  }
}

bool Crowd::Free(const Eigen::Vector2d& p) const {
  const double r = options_.radius_m;
  const double res = collision_.resolution_m();
  const int reach = static_cast<int>(std::ceil(r / res));
  const auto centre = collision_.WorldToCell(p);
  if (!centre) return false;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const nav::CellIndex c{centre->x + dx, centre->y + dy};
      if (!collision_.Contains(c)) return false;
      if (collision_.at(c) >= nav::kOccupiedCell && (collision_.CellCenter(c) - p).norm() < r) return false;
    }
  }
  return true;
}

void Crowd::Step(double dt_s, const std::optional<OrcaNeighbour>& robot) {
  const CrowdOptions& o = options_;
  std::vector<Eigen::Vector2d> next(pedestrians_.size(), Eigen::Vector2d::Zero());
  std::vector<OrcaNeighbour> neighbours;
  for (std::size_t i = 0; i < pedestrians_.size(); ++i) {
    Pedestrian& p = pedestrians_[i];
    const Eigen::Vector2d& goal = p.returning ? p.route.start : p.route.goal;
    if ((goal - p.position).norm() < o.goal_tolerance_m) {
      if (o.turn_back) {
        p.returning = !p.returning;
      } else {
        p.arrived = true;
      }
    }
    if (p.arrived) continue;  // stands: next[i] stays zero
    const Eigen::Vector2d to_goal = (p.returning ? p.route.start : p.route.goal) - p.position;
    const double distance = to_goal.norm();
    const Eigen::Vector2d preferred = distance > kEpsilon
                                          ? Eigen::Vector2d(Eigen::Rotation2Dd(-o.keep_right_rad) * to_goal / distance *
                                                            std::min(o.preferred_speed_mps, distance / dt_s))
                                          : Eigen::Vector2d::Zero();
    neighbours.clear();
    for (std::size_t j = 0; j < pedestrians_.size(); ++j) {
      const Pedestrian& other = pedestrians_[j];
      if (j == i || (other.position - p.position).norm() > o.neighbour_distance_m) continue;
      // Someone standing for good takes no part in the avoidance: they are passed like an obstacle.
      neighbours.push_back({other.position, other.velocity, o.radius_m, !other.arrived});
    }
    for (const StaticObstacle& s : obstacles_) {
      if ((s.center - p.position).norm() > o.neighbour_distance_m) continue;
      neighbours.push_back({s.center, Eigen::Vector2d::Zero(), s.bounding_radius_m(), false});
    }
    if (o.see_robot && robot && (robot->position - p.position).norm() <= o.neighbour_distance_m) {
      neighbours.push_back(*robot);
    }
    next[i] = OrcaVelocity(p.position, p.velocity, o.radius_m, preferred, o.max_speed_mps, o.time_horizon_s, dt_s,
                           neighbours);
  }
  for (std::size_t i = 0; i < pedestrians_.size(); ++i) {
    Pedestrian& p = pedestrians_[i];
    p.velocity = next[i];
    const Eigen::Vector2d step = p.velocity * dt_s;
    // Walls: slide along them rather than through.
    if (Free(p.position + step)) {
      p.position += step;
    } else if (Free(p.position + Eigen::Vector2d(step.x(), 0.0))) {
      p.position.x() += step.x();
      p.velocity.y() = 0.0;
    } else if (Free(p.position + Eigen::Vector2d(0.0, step.y()))) {
      p.position.y() += step.y();
      p.velocity.x() = 0.0;
    } else {
      p.velocity.setZero();
    }
  }
}

TriangleMesh Crowd::Mesh() const {
  TriangleMesh mesh;
  for (const Pedestrian& p : pedestrians_) {
    mesh.AddCylinder(p.position.cast<float>(), static_cast<float>(options_.radius_m),
                     static_cast<float>(options_.height_m), kPrismSides, kPersonColor);
  }
  return mesh;
}

std::vector<PedestrianRoute> RandomRoutes(const nav::OccupancyGrid& collision, int count, double radius_m,
                                          const RouteArea& area, std::mt19937& rng) {
  // Free cells with room for a person and a margin.
  const double margin = radius_m + 0.15;
  const double res = collision.resolution_m();
  const int reach = static_cast<int>(std::ceil(margin / res));
  const auto clear_at = [&](const Eigen::Vector2d& p) {
    if (area.contains && !area.contains(p)) return false;
    const auto c = collision.WorldToCell(p);
    if (!c) return false;
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const nav::CellIndex n{c->x + dx, c->y + dy};
        if (!collision.Contains(n) || collision.at(n) >= nav::kOccupiedCell || collision.at(n) < 0) return false;
      }
    }
    return true;
  };
  const auto line_clear = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const int steps = static_cast<int>(std::ceil((b - a).norm() / res));
    for (int s = 0; s <= steps; ++s) {
      if (!clear_at(a + (b - a) * (static_cast<double>(s) / std::max(steps, 1)))) return false;
    }
    return true;
  };
  const auto in_range = [&](const Eigen::Vector2d& p) {
    const double d = (p - area.center).norm();
    return d >= area.clearance_m && d <= area.within_m;
  };
  const auto apart = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - b).norm() > 2.0 * margin + 0.2;
  };
  // Sampled over the part of the grid within reach of the centre.
  const double x0 = collision.origin().x_m;
  const double y0 = collision.origin().y_m;
  std::uniform_real_distribution<double> ux(std::max(x0, area.center.x() - area.within_m),
                                            std::min(x0 + collision.width() * res, area.center.x() + area.within_m));
  std::uniform_real_distribution<double> uy(std::max(y0, area.center.y() - area.within_m),
                                            std::min(y0 + collision.height() * res, area.center.y() + area.within_m));
  std::uniform_real_distribution<double> length(area.min_length_m, area.max_length_m);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::vector<PedestrianRoute> routes;
  for (int attempt = 0; attempt < 20000 && static_cast<int>(routes.size()) < count; ++attempt) {
    const Eigen::Vector2d start(ux(rng), uy(rng));
    if (!in_range(start) || !clear_at(start)) continue;
    const double a = angle(rng);
    const Eigen::Vector2d goal = start + length(rng) * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (!clear_at(goal) || !line_clear(start, goal)) continue;
    const bool ok = std::all_of(routes.begin(), routes.end(), [&](const PedestrianRoute& r) {
      return apart(r.start, start) && (!area.goals_apart || apart(r.goal, goal));
    });
    if (ok) routes.push_back({start, goal});
  }
  return routes;
}

}  // namespace corridor::drivers::sim
