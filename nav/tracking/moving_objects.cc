#include "nav/tracking/moving_objects.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

MovingObjectOptions ForDepthCamera(MovingObjectOptions options) {
  options.map_clearance_m = std::max(options.map_clearance_m, 0.25);
  return options;
}

MovingObjectTracker::MovingObjectTracker(const MovingObjectOptions& options) : options_(options) {
  if (options.window_scans < 2) throw std::invalid_argument("tracking: window_scans must be at least 2");
  if (!(options.cluster_distance_m > 0.0)) throw std::invalid_argument("tracking: cluster_distance_m must be > 0");
  if (!(options.time_scale_mps > 0.0)) throw std::invalid_argument("tracking: time_scale_mps must be > 0");
  if (options.min_points < 2) throw std::invalid_argument("tracking: min_points must be at least 2");
  if (!(options.range_m > 0.0)) throw std::invalid_argument("tracking: range_m must be > 0");
  if (options.unseen_coast_s < options.coast_s || options.merged_hold_s < options.coast_s ||
      options.unseen_edge_m < 0.0) {
    throw std::invalid_argument(
        "tracking: need unseen_coast_s >= coast_s, merged_hold_s >= coast_s and unseen_edge_m >= 0");
  }
  if (options.gate_growth_mps < 0.0 || options.max_gate_m < options.gate_m) {
    throw std::invalid_argument("tracking: need gate_growth_mps >= 0 and max_gate_m >= gate_m");
  }
}

void MovingObjectTracker::SetMap(std::shared_ptr<const OccupancyGrid> map) {
  map_ = std::move(map);
  map_reach_ = map_ ? static_cast<int>(std::ceil(options_.map_clearance_m / map_->resolution_m())) : 0;
}

void MovingObjectTracker::Clear() {
  scans_.clear();
  tracks_.clear();
  walk_ends_.clear();
  newest_on_map_.clear();
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
                                                              const std::vector<Eigen::Vector2d>& world_points,
                                                              const std::optional<SensorView>& view) {
  if (!scans_.empty() && stamp_s < newest_stamp_s_) Clear();
  newest_stamp_s_ = stamp_s;
  newest_on_map_.clear();
  std::vector<Point> scan;
  for (const Eigen::Vector2d& p : world_points) {
    if ((p - sensor).norm() > options_.range_m) continue;
    if (OnMap(p)) {
      newest_on_map_.push_back(p);
    } else {
      scan.push_back({p, stamp_s});
    }
  }
  // An empty scan (everything on the map) still takes its place in the window.
  scans_.push_back({stamp_s, std::move(scan)});
  while (static_cast<int>(scans_.size()) > options_.window_scans) scans_.pop_front();
  UpdateTracks(stamp_s, FindClusters(), view);
  return now_.objects;
}

void MovingObjectTracker::Cluster::Measure() {
  position = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : newest) position += p;
  position /= static_cast<double>(newest.size());
  radius_m = 0.0;
  for (const Eigen::Vector2d& p : newest) radius_m = std::max(radius_m, (p - position).norm());
}

std::vector<MovingObjectTracker::Cluster> MovingObjectTracker::FindClusters() const {
  const MovingObjectOptions& o = options_;
  std::vector<Point> points;
  for (const auto& scan : scans_) points.insert(points.end(), scan.points.begin(), scan.points.end());
  const std::size_t newest_begin = points.size() - scans_.back().points.size();

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

  std::unordered_map<std::size_t, std::vector<std::size_t>> members_of;  // root -> members, in time order
  for (std::size_t i = 0; i < points.size(); ++i) members_of[sets.Find(i)].push_back(i);

  std::vector<Cluster> clusters;
  for (const auto& [root, members] : members_of) {
    if (static_cast<int>(members.size()) < o.min_points) continue;  // noise
    Cluster c;
    for (const std::size_t i : members) {
      if (i >= newest_begin) c.newest.push_back(points[i].xy);
    }
    if (c.newest.empty()) continue;  // gone from view: nothing to report
    c.points = static_cast<int>(members.size());
    c.Measure();
    const double span = points[members.back()].t - points[members.front()].t;
    if (span < o.min_span_s) {
      clusters.push_back(std::move(c));
      continue;
    }
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
    if (dt > 1e-6) c.velocity = (upper / n_upper - lower / n_lower) / dt;
    clusters.push_back(std::move(c));
  }
  // The clusters' hash order is arbitrary: sort, so that the same scans give the same tracks.
  std::sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) {
    return a.position.x() != b.position.x() ? a.position.x() < b.position.x() : a.position.y() < b.position.y();
  });
  return clusters;
}

void MovingObjectTracker::UpdateTracks(double stamp_s, const std::vector<Cluster>& clusters,
                                       const std::optional<SensorView>& view) {
  const MovingObjectOptions& o = options_;
  for (Track& t : tracks_) {
    // Out of view, someone walking toward the known end of their walk turns round there.
    const std::optional<Eigen::Vector2d> end = t.out_of_view ? WalkEndAhead(t) : std::nullopt;
    t.position += (stamp_s - t.stamp_s) * t.velocity;
    t.stamp_s = stamp_s;
    if (end && (t.position - *end).dot(t.velocity) > 0.0) t.velocity = -t.velocity;
  }
  // Nearest-neighbour association, closest pairs first; a cluster may take several tracks (people side by side),
  // a track one cluster.
  struct Pair {
    double distance;
    std::size_t track;
    std::size_t cluster;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const double unseen_s = stamp_s - tracks_[i].last_seen_s;
    const double gate = std::min(o.gate_m + o.gate_growth_mps * unseen_s, o.max_gate_m);
    for (std::size_t j = 0; j < clusters.size(); ++j) {
      double d = std::numeric_limits<double>::infinity();
      for (const auto& p : clusters[j].newest) d = std::min(d, (p - tracks_[i].position).norm());
      if (d <= gate) pairs.push_back({d, i, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.distance < b.distance; });
  std::vector<int> cluster_of(tracks_.size(), -1);
  std::vector<int> tracks_in(clusters.size(), 0);
  for (const Pair& p : pairs) {
    if (cluster_of[p.track] >= 0) continue;
    cluster_of[p.track] = static_cast<int>(p.cluster);
    ++tracks_in[p.cluster];
  }
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (cluster_of[i] < 0) continue;
    const Cluster& c = clusters[static_cast<std::size_t>(cluster_of[i])];
    const bool alone = tracks_in[static_cast<std::size_t>(cluster_of[i])] == 1 && c.radius_m <= o.merged_radius_m;
    if (!alone) continue;  // sharing a cluster: coast on the prediction
    Track& t = tracks_[i];
    t.position = c.position;
    t.radius_m = c.radius_m;
    t.points = c.points;
    t.last_seen_s = stamp_s;
    See(t, stamp_s, c);
    NoteTurn(t, stamp_s);
  }
  // A cluster several tracks share (people walking together, or crossing) is split among them: each track takes the
  // newest scan's points nearer its own centre than the others' (a few k-means steps from the predictions), so that
  // it follows its own person rather than drifting on its prediction.
  for (std::size_t j = 0; j < clusters.size(); ++j) {
    if (tracks_in[j] < 2) continue;
    std::vector<std::size_t> sharing;
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
      if (cluster_of[i] == static_cast<int>(j)) sharing.push_back(i);
    }
    SplitAmong(stamp_s, clusters[j], sharing);
  }
  // New clusters start tracks.
  for (std::size_t j = 0; j < clusters.size(); ++j) {
    if (tracks_in[j] > 0) continue;
    const Cluster& c = clusters[j];
    const bool single = c.radius_m <= o.merged_radius_m;
    Track t{next_id_++, c.position, single && c.velocity ? *c.velocity : Eigen::Vector2d::Zero(),
            c.radius_m, c.points,   stamp_s,
            stamp_s,    {},         -std::numeric_limits<double>::infinity()};
    if (single) t.seen.push_back({stamp_s, c.position, c.radius_m, true});
    tracks_.push_back(std::move(t));
    cluster_of.push_back(static_cast<int>(j));
  }
  // Tracks not seen alone for a while end (with their cluster index, kept alongside); moving ones outside the view
  // later.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    t.out_of_view = view && t.velocity.norm() >= o.moving_speed_mps && !view->Covers(t.position, o.unseen_edge_m);
    if (t.out_of_view) {
      t.out_of_view_s = stamp_s;
      t.walked = Eigen::Vector2d::Zero();  // a turn made out of view is not seen: not the end of its walk
    }
    const double unseen_s = stamp_s - t.last_seen_s;
    const bool held = cluster_of[i] >= 0 && unseen_s <= o.merged_hold_s;
    // Out of view, kept on its prediction; in view, not seen there for coast_s is gone.
    const bool gone =
        t.out_of_view ? unseen_s > o.unseen_coast_s : stamp_s - std::max(t.last_seen_s, t.out_of_view_s) > o.coast_s;
    if (!held && gone) continue;
    tracks_[kept] = tracks_[i];
    cluster_of[kept] = cluster_of[i];
    ++kept;
  }
  tracks_.resize(kept);
  cluster_of.resize(kept);
  // Ends of walks are forgotten after a while.
  walk_ends_.erase(std::remove_if(walk_ends_.begin(), walk_ends_.end(),
                                  [&](const WalkEnd& e) { return stamp_s - e.stamp_s > o.walk_end_memory_s; }),
                   walk_ends_.end());

  now_.objects.clear();
  now_.static_points.clear();
  std::vector<bool> cluster_moves(clusters.size(), false);
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const Track& t = tracks_[i];
    TrackedObject object;
    object.id = t.id;
    object.position = t.position;
    object.radius_m = t.radius_m;
    object.points = t.points;
    object.seen = t.last_seen_s == stamp_s;
    if (t.velocity.norm() >= o.moving_speed_mps) {
      object.velocity = t.velocity;
      object.moving = true;
      object.turn_at = WalkEndAhead(t);
    }
    if (cluster_of[i] >= 0 && object.moving) cluster_moves[static_cast<std::size_t>(cluster_of[i])] = true;
    now_.objects.push_back(object);
  }
  // Static points: the newest scan's on the map, and those of every cluster that no moving track holds.
  now_.static_points = newest_on_map_;
  for (std::size_t j = 0; j < clusters.size(); ++j) {
    if (cluster_moves[j]) continue;
    now_.static_points.insert(now_.static_points.end(), clusters[j].newest.begin(), clusters[j].newest.end());
  }
  std::sort(now_.objects.begin(), now_.objects.end(), [](const TrackedObject& a, const TrackedObject& b) {
    return a.position.x() != b.position.x() ? a.position.x() < b.position.x() : a.position.y() < b.position.y();
  });
}

void MovingObjectTracker::SplitAmong(double stamp_s, const Cluster& cluster, const std::vector<std::size_t>& sharing) {
  constexpr int kSteps = 3;
  constexpr std::size_t kMinPoints = 3;  // a share smaller than this is a sliver: the track coasts on
  // Each track's share, centred first on its prediction.
  std::vector<Cluster> shares(sharing.size());
  for (std::size_t k = 0; k < sharing.size(); ++k) shares[k].position = tracks_[sharing[k]].position;
  for (int step = 0; step < kSteps; ++step) {
    for (Cluster& share : shares) share.newest.clear();
    for (const Eigen::Vector2d& p : cluster.newest) {
      std::size_t nearest = 0;
      for (std::size_t k = 1; k < shares.size(); ++k) {
        if ((p - shares[k].position).squaredNorm() < (p - shares[nearest].position).squaredNorm()) nearest = k;
      }
      shares[nearest].newest.push_back(p);
    }
    for (Cluster& share : shares) {
      if (!share.newest.empty()) share.Measure();
    }
  }
  for (std::size_t k = 0; k < sharing.size(); ++k) {
    const Cluster& own = shares[k];
    if (own.newest.size() < kMinPoints) continue;
    Track& t = tracks_[sharing[k]];
    t.position = own.position;
    t.radius_m = own.radius_m;
    See(t, stamp_s, own);  // no velocity of its own: the track's is kept unless its positions show a turn
  }
}

void MovingObjectTracker::See(Track& t, double stamp_s, const Cluster& c) const {
  const MovingObjectOptions& o = options_;
  const double window_begin_s = scans_.front().stamp_s;
  while (!t.seen.empty() && t.seen.front().stamp_s < window_begin_s - o.recent_s) t.seen.pop_front();
  // A person partly hidden behind another shows a sliver whose centroid stalls: not a change of velocity.
  double widest = 0.0;
  for (const Sighting& s : t.seen) widest = std::max(widest, s.whole ? s.radius_m : 0.0);
  t.seen.push_back({stamp_s, c.position, c.radius_m, c.radius_m >= o.partial_fraction * widest});

  // The velocity over the last recent_s, from whole sightings in every scan since (a track coming out of a merged
  // cluster jumps).
  const auto then = std::find_if(t.seen.rbegin(), t.seen.rend(),
                                 [&](const Sighting& s) { return stamp_s - s.stamp_s >= o.recent_s - 1e-6; });
  if (then != t.seen.rend()) {
    const auto sightings = then - t.seen.rbegin() + 1;
    const auto scans =
        std::count_if(scans_.begin(), scans_.end(), [&](const Scan& scan) { return scan.stamp_s >= then->stamp_s; });
    const bool whole = std::all_of(t.seen.rbegin(), then + 1, [](const Sighting& s) { return s.whole; });
    const Eigen::Vector2d recent = (c.position - then->position) / (stamp_s - then->stamp_s);
    if (sightings == scans && whole && (recent - t.velocity).norm() > o.maneuver_mps) {
      t.velocity = recent;
      t.maneuver_s = then->stamp_s;
      return;
    }
  }
  if (t.maneuver_s < window_begin_s) {
    if (c.velocity) t.velocity = o.velocity_gain * *c.velocity + (1.0 - o.velocity_gain) * t.velocity;
    return;
  }
  // The window still holds scans from before the change: a least-squares line through the track's own whole
  // sightings since then.
  double n = 0.0;
  double t_mean = 0.0;
  Eigen::Vector2d p_mean = Eigen::Vector2d::Zero();
  for (const Sighting& s : t.seen) {
    if (s.stamp_s < t.maneuver_s || !s.whole) continue;
    n += 1.0;
    t_mean += s.stamp_s;
    p_mean += s.position;
  }
  if (n < 2.0) return;
  t_mean /= n;
  p_mean /= n;
  double tt = 0.0;
  Eigen::Vector2d tp = Eigen::Vector2d::Zero();
  for (const Sighting& s : t.seen) {
    if (s.stamp_s < t.maneuver_s || !s.whole) continue;
    tt += (s.stamp_s - t_mean) * (s.stamp_s - t_mean);
    tp += (s.stamp_s - t_mean) * (s.position - p_mean);
  }
  if (tt > 1e-9) t.velocity = tp / tt;
}

void MovingObjectTracker::NoteTurn(Track& t, double stamp_s) {
  const MovingObjectOptions& o = options_;
  const double speed = t.velocity.norm();
  if (speed < o.moving_speed_mps) return;
  const double walked = t.walked.norm();
  if (walked > 0.0 && t.velocity.dot(t.walked) < o.turn_cos * speed * walked) {
    // The turn was seen within recent_s: the farthest whole sighting along the old heading is where it was.
    const Eigen::Vector2d heading = t.walked / walked;
    std::optional<Eigen::Vector2d> apex;
    for (const Sighting& s : t.seen) {
      if (s.whole && (!apex || s.position.dot(heading) > apex->dot(heading))) apex = s.position;
    }
    if (apex) {
      // The same end found again replaces the old one.
      const auto same = std::find_if(walk_ends_.begin(), walk_ends_.end(), [&](const WalkEnd& e) {
        return (e.position - *apex).norm() < 2.0 * o.walk_end_lateral_m && e.heading.dot(heading) > 0.7;
      });
      if (same != walk_ends_.end()) walk_ends_.erase(same);
      walk_ends_.push_back({*apex, heading, stamp_s, t.id});
    }
  }
  t.walked = t.velocity;
}

std::optional<Eigen::Vector2d> MovingObjectTracker::WalkEndAhead(const Track& t) const {
  const MovingObjectOptions& o = options_;
  const Eigen::Vector2d heading = t.velocity.normalized();
  std::optional<Eigen::Vector2d> nearest;
  double nearest_ahead = o.walk_end_reach_m;
  for (const WalkEnd& e : walk_ends_) {
    // Another track's end only once that track is gone (the same person, lost and found again): two people pacing
    // side by side each have their own.
    const auto alive = [&](const Track& u) { return u.id == e.track; };
    if (e.track != t.id && std::any_of(tracks_.begin(), tracks_.end(), alive)) continue;
    if (e.heading.dot(heading) < 0.8) continue;
    const Eigen::Vector2d to = e.position - t.position;
    const double ahead = to.dot(heading);
    const double aside = std::abs(heading.x() * to.y() - heading.y() * to.x());
    if (ahead > 0.0 && ahead <= nearest_ahead && aside <= o.walk_end_lateral_m) {
      nearest = e.position;
      nearest_ahead = ahead;
    }
  }
  return nearest;
}

}  // namespace corridor::nav
