#include "nav/planner/planner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

// Whether `ok(point, cell)` holds at every half-cell sample of the segment a-b (false where a sample is off the map).
template <typename Ok>
bool EverySample(const Costmap& costmap, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Ok& ok) {
  const double step = costmap.grid().resolution_m() / 2.0;
  const int samples = static_cast<int>(std::ceil((b - a).norm() / step)) + 1;
  for (int i = 0; i <= samples; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / samples);
    const auto c = costmap.grid().WorldToCell(p);
    if (!c || !ok(p, costmap.Index(*c))) return false;
  }
  return true;
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Douglas-Peucker that also refuses a shortcut through cells the robot may not enter.
void Simplify(const Costmap& costmap, const std::vector<Eigen::Vector2d>& points, std::size_t first, std::size_t last,
              double tolerance, std::vector<std::size_t>& keep) {
  if (last <= first + 1) return;
  double worst = -1.0;
  std::size_t worst_index = first + 1;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = DistanceToSegment(points[i], points[first], points[last]);
    if (d > worst) {
      worst = d;
      worst_index = i;
    }
  }
  if (worst <= tolerance && SegmentTraversable(costmap, points[first], points[last])) return;
  Simplify(costmap, points, first, worst_index, tolerance, keep);
  keep.push_back(worst_index);
  Simplify(costmap, points, worst_index, last, tolerance, keep);
}

}  // namespace

bool SegmentTraversable(const Costmap& costmap, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return EverySample(costmap, a, b,
                     [&](const Eigen::Vector2d&, std::size_t cell) { return costmap.Traversable(cell); });
}

bool RestOfPathTraversable(const Costmap& costmap, const std::vector<Waypoint>& path, const Eigen::Vector2d& from,
                           double band_reach_m) {
  std::size_t nearest = 0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    if ((path[i].pose.translation() - from).norm() < (path[nearest].pose.translation() - from).norm()) nearest = i;
  }
  // Near the robot the path may cross the inflated band (its way out of it: AStar); an obstacle there, or anything
  // but traversable cells farther on, and it no longer stands.
  const auto stands = [&](const Eigen::Vector2d& p, std::size_t cell) {
    if (costmap.Traversable(cell)) return true;
    const double away = (p - from).norm();
    const bool under_robot = away <= costmap.options().robot_radius_m && !costmap.InKeepOut(cell);
    return (!costmap.IsObstacle(cell) || under_robot) && away <= band_reach_m;
  };
  for (std::size_t i = std::max<std::size_t>(nearest, 1); i < path.size(); ++i) {
    if (!EverySample(costmap, path[i - 1].pose.translation(), path[i].pose.translation(), stands)) return false;
  }
  return true;
}

std::vector<float> ExtraCosts(const Costmap& costmap, std::span<const float> traffic,
                              std::span<const Eigen::Vector2d> blocking, double radius_m, float cost) {
  const std::size_t cells = static_cast<std::size_t>(costmap.width()) * static_cast<std::size_t>(costmap.height());
  std::vector<float> extra;
  if (traffic.size() == cells) extra.assign(traffic.begin(), traffic.end());
  if (!blocking.empty()) AddPointCost(costmap, blocking, radius_m, cost, extra);
  return extra;
}

bool PathsDiverge(const std::vector<Eigen::Vector2d>& candidate, const std::vector<Eigen::Vector2d>& current,
                  double along_m, double tolerance_m) {
  if (current.empty()) return !candidate.empty();
  const auto distance_to_current = [&](const Eigen::Vector2d& p) {
    double best = (p - current.front()).norm();
    for (std::size_t i = 1; i < current.size(); ++i) {
      const Eigen::Vector2d ab = current[i] - current[i - 1];
      const double t =
          ab.squaredNorm() > 0.0 ? std::clamp((p - current[i - 1]).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      best = std::min(best, (p - (current[i - 1] + t * ab)).norm());
    }
    return best;
  };
  double travelled = 0.0;
  for (std::size_t i = 0; i < candidate.size() && travelled <= along_m; ++i) {
    if (i > 0) travelled += (candidate[i] - candidate[i - 1]).norm();
    if (distance_to_current(candidate[i]) > tolerance_m) return true;
  }
  return false;
}

void AddPointCost(const Costmap& costmap, std::span<const Eigen::Vector2d> points, double radius_m, float cost,
                  std::vector<float>& extra) {
  const std::size_t cells = static_cast<std::size_t>(costmap.width()) * static_cast<std::size_t>(costmap.height());
  if (extra.empty()) extra.assign(cells, 0.0f);
  if (extra.size() != cells) throw std::invalid_argument("AddPointCost: extra costs must have one value per cell");
  if (!(cost >= 0.0f)) throw std::invalid_argument("AddPointCost: cost must be non-negative");
  const OccupancyGrid& grid = costmap.grid();
  const int reach = static_cast<int>(std::ceil(radius_m / grid.resolution_m()));
  std::vector<bool> done(cells, false);  // a cell near several points takes the cost once
  for (const Eigen::Vector2d& p : points) {
    const auto centre = grid.WorldToCell(p);
    if (!centre) continue;
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const CellIndex c{centre->x + dx, centre->y + dy};
        if (!grid.Contains(c) || (grid.CellCenter(c) - p).norm() > radius_m) continue;
        const std::size_t i = costmap.Index(c);
        if (done[i]) continue;
        done[i] = true;
        extra[i] += cost;
      }
    }
  }
}

PlanResult PlanPath(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                    std::optional<double> goal_yaw, const std::atomic<bool>* cancel, const PathOptions& options) {
  SearchResult search = AStar(costmap, start, goal, cancel, options.extra_cost, options.robot_at_start);
  PlanResult result{search.error, search.detail, {}};
  if (!result.ok()) return result;
  Plan& plan = result.plan;
  plan.expanded = search.path.expanded;

  // The dense path runs from the exact start through the cell centres to the exact goal.
  const OccupancyGrid& grid = costmap.grid();
  plan.dense.push_back(start);
  for (std::size_t i = 1; i + 1 < search.path.cells.size(); ++i)
    plan.dense.push_back(grid.CellCenter(search.path.cells[i]));
  plan.dense.push_back(goal);
  double clearance_sum = 0.0;
  plan.min_clearance_m = std::numeric_limits<double>::infinity();
  const double cap = costmap.options().robot_radius_m + costmap.options().saturation_m + grid.resolution_m();
  for (const CellIndex& c : search.path.cells) {
    const double clearance = std::min<double>(costmap.clearance_m(costmap.Index(c)), cap);
    plan.min_clearance_m = std::min(plan.min_clearance_m, clearance);
    clearance_sum += clearance;
  }
  plan.mean_clearance_m = clearance_sum / static_cast<double>(search.path.cells.size());
  for (std::size_t i = 1; i < plan.dense.size(); ++i) plan.length_m += (plan.dense[i] - plan.dense[i - 1]).norm();

  std::vector<std::size_t> keep = {0};
  Simplify(costmap, plan.dense, 0, plan.dense.size() - 1, options.simplify_tolerance_m, keep);
  keep.push_back(plan.dense.size() - 1);
  // A path that crosses the inflated band (a way out of it, or off an island of free space ringed by it) crawls from
  // its start until it is across: on an island too the way out is tight, and the follower cuts corners at speed.
  std::size_t crawl_until = 0;
  for (std::size_t i = 0; i < search.path.cells.size(); ++i) {
    if (!costmap.Traversable(costmap.Index(search.path.cells[i]))) crawl_until = i + 1;
  }
  std::size_t previous = 0;
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const Eigen::Vector2d& p = plan.dense[keep[k]];
    Waypoint w;
    w.pose.x_m = p.x();
    w.pose.y_m = p.y();
    // The speed limit on the way here: the lowest over the searched cells between the two waypoints; until across
    // the inflated band, kBandSpeedMps.
    for (std::size_t i = previous; i <= keep[k] && i < search.path.cells.size(); ++i) {
      const std::size_t cell = costmap.Index(search.path.cells[i]);
      w.speed_limit_mps = std::min<double>(w.speed_limit_mps, costmap.speed_limit_mps(cell));
      if (i < crawl_until) w.speed_limit_mps = std::min(w.speed_limit_mps, kBandSpeedMps);
    }
    previous = keep[k];
    plan.waypoints.push_back(w);
  }
  for (std::size_t k = 0; k + 1 < plan.waypoints.size(); ++k) {
    const Eigen::Vector2d d = plan.waypoints[k + 1].pose.translation() - plan.waypoints[k].pose.translation();
    plan.waypoints[k].pose.yaw_rad = std::atan2(d.y(), d.x());
  }
  Waypoint& last = plan.waypoints.back();
  if (goal_yaw) {
    last.pose.yaw_rad = WrapAngle(*goal_yaw);
  } else if (plan.waypoints.size() >= 2) {
    last.pose.yaw_rad = plan.waypoints[plan.waypoints.size() - 2].pose.yaw_rad;
  }
  return result;
}

}  // namespace corridor::nav
