#include "nav/tracking/moving_objects.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace corridor::nav {
namespace {

// Union-find over point indices, with path halving.
struct DisjointSets {
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t Find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void Join(std::size_t a, std::size_t b) { parent[Find(a)] = Find(b); }
  std::vector<std::size_t> parent;
};

std::int64_t CellKey(std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffff); }

}  // namespace

std::vector<Eigen::Vector2d> ScanToWorld(const Pose2& world_T_sensor, double angle_min_rad, double increment_rad,
                                         double range_min_m, double range_max_m, const std::vector<float>& ranges) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(ranges.size());
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    if (!std::isfinite(r) || r < range_min_m || r > range_max_m) continue;
    const double a = angle_min_rad + static_cast<double>(i) * increment_rad;
    points.push_back(world_T_sensor.Transform(Eigen::Vector2d(r * std::cos(a), r * std::sin(a))));
  }
  return points;
}

MovingObjectTracker::MovingObjectTracker(const MovingObjectOptions& options) : options_(options) {
  if (options.window_scans < 2) throw std::invalid_argument("tracking: window_scans must be at least 2");
  if (!(options.cluster_distance_m > 0.0)) throw std::invalid_argument("tracking: cluster_distance_m must be > 0");
  if (!(options.time_scale_mps > 0.0)) throw std::invalid_argument("tracking: time_scale_mps must be > 0");
  if (options.min_points < 2) throw std::invalid_argument("tracking: min_points must be at least 2");
  if (!(options.range_m > 0.0)) throw std::invalid_argument("tracking: range_m must be > 0");
}

void MovingObjectTracker::SetMap(std::shared_ptr<const OccupancyGrid> map) {
  map_ = std::move(map);
  map_reach_ = map_ ? static_cast<int>(std::ceil(options_.map_clearance_m / map_->resolution_m())) : 0;
}

void MovingObjectTracker::Clear() {
  scans_.clear();
  newest_all_.clear();
  now_.objects.clear();
  now_.static_points.clear();
}

bool MovingObjectTracker::OnMap(const Eigen::Vector2d& p) const {
  if (!map_) return false;
  const auto cell = map_->WorldToCell(p);
  if (!cell) return false;
  for (int dy = -map_reach_; dy <= map_reach_; ++dy) {
    for (int dx = -map_reach_; dx <= map_reach_; ++dx) {
      const CellIndex c{cell->x + dx, cell->y + dy};
      if (map_->Contains(c) && map_->at(c) >= kOccupiedCell) return true;
    }
  }
  return false;
}

const std::vector<TrackedObject>& MovingObjectTracker::Update(double stamp_s, const Eigen::Vector2d& sensor,
                                                              const std::vector<Eigen::Vector2d>& world_points) {
  if (!scans_.empty() && stamp_s < newest_stamp_s_) Clear();
  newest_stamp_s_ = stamp_s;
  newest_all_.clear();
  std::vector<Point> scan;
  for (const Eigen::Vector2d& p : world_points) {
    if ((p - sensor).norm() > options_.range_m) continue;
    newest_all_.push_back(p);
    if (!OnMap(p)) scan.push_back({p, stamp_s});
  }
  // An empty scan (everything on the map) still takes its place in the window.
  scans_.push_back(std::move(scan));
  while (static_cast<int>(scans_.size()) > options_.window_scans) scans_.pop_front();
  Cluster();
  return now_.objects;
}

void MovingObjectTracker::Cluster() {
  const MovingObjectOptions& o = options_;
  std::vector<Point> points;
  for (const auto& scan : scans_) points.insert(points.end(), scan.begin(), scan.end());
  const std::size_t newest_begin = points.size() - scans_.back().size();

  // Euclidean clustering in (x, y, t * scale): every pair nearer than cluster_distance_m joins, found through a
  // uniform grid in (x, y) of that cell size (the window's time span is short, so time needs no cells of its own).
  const double cell = o.cluster_distance_m;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid;
  const auto cell_of = [&](const Eigen::Vector2d& p) {
    return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(std::floor(p.x() / cell)),
                                                 static_cast<std::int64_t>(std::floor(p.y() / cell))};
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [cx, cy] = cell_of(points[i].xy);
    grid[CellKey(cx, cy)].push_back(i);
  }
  DisjointSets sets(points.size());
  const double d2 = o.cluster_distance_m * o.cluster_distance_m;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [cx, cy] = cell_of(points[i].xy);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        const auto found = grid.find(CellKey(cx + dx, cy + dy));
        if (found == grid.end()) continue;
        for (const std::size_t j : found->second) {
          if (j <= i) continue;
          const double dt = (points[j].t - points[i].t) * o.time_scale_mps;
          if ((points[j].xy - points[i].xy).squaredNorm() + dt * dt < d2) sets.Join(i, j);
        }
      }
    }
  }

  std::unordered_map<std::size_t, std::vector<std::size_t>> clusters;  // root -> members, in time order
  for (std::size_t i = 0; i < points.size(); ++i) clusters[sets.Find(i)].push_back(i);

  now_.objects.clear();
  now_.static_points.clear();
  // Map points of the newest scan are static; object points are added below unless they move.
  for (const Eigen::Vector2d& p : newest_all_) {
    if (OnMap(p)) now_.static_points.push_back(p);
  }
  for (const auto& [root, members] : clusters) {
    std::vector<Eigen::Vector2d> newest;
    for (const std::size_t i : members) {
      if (i >= newest_begin) newest.push_back(points[i].xy);
    }
    if (newest.empty()) continue;  // gone from view: nothing to report
    TrackedObject object;
    object.points = static_cast<int>(members.size());
    for (const auto& p : newest) object.position += p;
    object.position /= static_cast<double>(newest.size());
    for (const auto& p : newest) object.radius_m = std::max(object.radius_m, (p - object.position).norm());
    const double span = points[members.back()].t - points[members.front()].t;
    if (static_cast<int>(members.size()) >= o.min_points && span >= o.min_span_s) {
      // Lower and upper halves along the time axis (members are in time order).
      const std::size_t half = members.size() / 2;
      Eigen::Vector2d lower = Eigen::Vector2d::Zero();
      Eigen::Vector2d upper = Eigen::Vector2d::Zero();
      double t_lower = 0.0;
      double t_upper = 0.0;
      for (std::size_t k = 0; k < members.size(); ++k) {
        const Point& p = points[members[k]];
        (k < half ? lower : upper) += p.xy;
        (k < half ? t_lower : t_upper) += p.t;
      }
      const auto n_lower = static_cast<double>(half);
      const auto n_upper = static_cast<double>(members.size() - half);
      const double dt = t_upper / n_upper - t_lower / n_lower;
      if (dt > 1e-6) {
        const Eigen::Vector2d velocity = (upper / n_upper - lower / n_lower) / dt;
        if (velocity.norm() >= o.moving_speed_mps) {
          object.velocity = velocity;
          object.moving = true;
        }
      }
    }
    if (!object.moving) now_.static_points.insert(now_.static_points.end(), newest.begin(), newest.end());
    if (static_cast<int>(members.size()) >= o.min_points) now_.objects.push_back(object);
  }
  // The clusters' hash order is arbitrary: sort, so that the same scans give the same list.
  std::sort(now_.objects.begin(), now_.objects.end(), [](const TrackedObject& a, const TrackedObject& b) {
    return a.position.x() != b.position.x() ? a.position.x() < b.position.x() : a.position.y() < b.position.y();
  });
}

}  // namespace corridor::nav
