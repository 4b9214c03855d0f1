// Moving objects from accumulated laser scans (Takiguchi et al.): the last few scans are stacked in the world
// frame with time as a third axis, so that a walking person leaves a slanted tube of points and a standing object
// a vertical one; the tubes are found by Euclidean clustering in (x, y, t * time_scale), and each cluster's
// velocity is the displacement between the centroids of its lower (older) and upper (newer) halves divided by
// the time between them.
//
// corridor's additions: points on the map's walls are dropped before clustering (they are not objects to
// track); each object carries the newest scan's extent, so that a caller can keep clear of it; and the clusters
// feed tracks kept from scan to scan (nearest-neighbour association, constant-velocity prediction), so that two
// people passing close to each other or walking together, whose points join into one cluster with a meaningless
// velocity, keep their own positions and velocities through it (the cluster's points are split among the tracks it
// holds, each keeping its velocity), and so that a person hidden behind another is still there for a short while.
//
// Clustering is written here (a uniform grid with union-find: only points in neighbouring cells are compared) rather
// than taken from OpenCV: cv::partition compares every pair, so its cost grows with the square of the window's
// points; see docs/design.md and bench/tracking_bench.cc.
#pragma once

#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/geometry/sensor_view.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct MovingObjectOptions {
  int window_scans = 10;             // Takiguchi's 10 accumulated scans
  double cluster_distance_m = 0.15;  // neighbours in (x, y, t * time_scale_mps) join a cluster
  double time_scale_mps = 0.5;       // one second of time is this far apart
  int min_points = 8;                // smaller clusters are noise
  double moving_speed_mps = 0.2;     // slower objects are reported as standing
  double min_span_s = 0.3;           // a cluster must cover this much time to give a velocity
  double map_clearance_m = 0.1;      // points this near an occupied map cell belong to the map
  double range_m = 6.0;              // points farther from the sensor are ignored
  double gate_m = 0.35;              // a cluster within this of a track's prediction (to its nearest point) is it
  // ...and a prediction grows less sure the longer the track has not been seen: its gate widens by this much per
  // second unseen, up to max_gate_m (someone who walked out of a camera's view and back into it is still them).
  double gate_growth_mps = 0.1;
  double max_gate_m = 0.8;
  double merged_radius_m = 0.45;  // a cluster this wide is taken for several objects: no velocity from it
  double coast_s = 0.8;           // a track not seen alone for this long is dropped...
  // ...unless it is in a cluster shared with other tracks (people walking together or crossing; it takes its own
  // part of the cluster's points) or too wide for one object: it is kept up to this long without being seen alone.
  double merged_hold_s = 3.0;
  double velocity_gain = 0.6;  // weight of a new velocity measurement against the track's
  // A person who turns round or sets off shows it in their own last few positions long before the window's halves
  // agree: when the track's velocity over the last recent_s differs from its estimate by more than maneuver_mps,
  // the track takes that recent velocity, and until the window holds only scans after the change, its velocity is
  // fitted to its own positions since then rather than taken from the cluster (whose halves straddle the turn).
  double recent_s = 0.3;
  double maneuver_mps = 0.5;
  double partial_fraction = 0.6;  // a sighting narrower than this part of the track's recent ones is partly hidden
  // People pace back and forth: where a track turned round (its heading changed by more than acos(turn_cos)) is
  // remembered for walk_end_memory_s as the end of a walk, and a person walking toward a remembered end the way it
  // was walked into (within walk_end_lateral_m of their line, at most walk_end_reach_m ahead) is reported with it,
  // so that a prediction can have them turn there rather than walk on through.
  double turn_cos = -0.5;
  double walk_end_memory_s = 60.0;
  double walk_end_lateral_m = 0.5;
  double walk_end_reach_m = 12.0;
  // A sensor that does not see all round (a camera: SensorView) cannot see that someone who walked out of its view
  // is gone: a moving track predicted outside the view (nearer than unseen_edge_m to its edge counts as outside: an
  // object cut by the edge is not seen whole) is kept on its prediction for unseen_coast_s instead of coast_s, turning
  // round at the known end of its walk. One predicted inside the view and not seen there for coast_s is dropped
  // (since it was last seen, or last predicted outside the view: coming back into view, it gets coast_s to be seen).
  double unseen_coast_s = 8.0;
  double unseen_edge_m = 0.3;
};

struct TrackedObject {
  int id = 0;                                          // the track's, the same from scan to scan
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // world frame: centroid of the newest scan's points (or the
                                                       // prediction, while the object is not seen alone)
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // world frame, m/s; zero when not moving
  double radius_m = 0.0;                               // the newest scan's points' largest distance from `position`
  bool moving = false;
  int points = 0;    // over the whole window
  bool seen = true;  // false: coasting on its prediction (merged with another, hidden, or out of
                     // the sensor's view)
  // Moving objects only: the remembered end of a walk ahead, where this object (or a track since lost) turned
  // round before when walking this way.
  std::optional<Eigen::Vector2d> turn_at;
};

// The options for scans made from a depth camera (nav/ground/depth_scan.h) instead of a laser: its depth noise grows
// with the square of the range, so that points on a wall stray farther from the map (map_clearance_m at least
// 0.25 m). The moving threshold stays the laser's: objects cut by the image's edges are left out of the scan, and
// with them the centroids that slid with the robot's motion (a threshold of 0.35 m/s, once needed, took people
// walking slowly, at 0.35 m/s, for standing objects; docs/benchmarks.md).
MovingObjectOptions ForDepthCamera(MovingObjectOptions options);

// What the laser shows around the robot after one scan: the objects and the points that stay where they are.
struct Surroundings {
  std::vector<TrackedObject> objects;
  std::vector<Eigen::Vector2d> static_points;  // world frame: walls and every object that is not moving
};

// The points of one scan in the world frame: ranges[i] along angle_min_rad + i * increment_rad from the sensor at
// `world_T_sensor`. Non-finite ranges and those outside [range_min_m, range_max_m] are skipped.
std::vector<Eigen::Vector2d> ScanToWorld(const Pose2& world_T_sensor, double angle_min_rad, double increment_rad,
                                         double range_min_m, double range_max_m, const std::vector<float>& ranges);

class MovingObjectTracker {
 public:
  explicit MovingObjectTracker(const MovingObjectOptions& options);  // throws std::invalid_argument for bad options

  // The static map whose walls are not objects (nullptr: none). Kept until replaced.
  void SetMap(std::shared_ptr<const OccupancyGrid> map);

  // Adds one scan taken at stamp_s from `sensor` (world frame), its points already in the world frame, drops the
  // oldest beyond the window, and clusters the window again. A stamp older than the newest scan clears the window
  // first (a clock reset or a replayed log). `view`: what the scan covers when it is not all round. Returns the
  // objects seen in the newest scan, and those kept on their predictions.
  const std::vector<TrackedObject>& Update(double stamp_s, const Eigen::Vector2d& sensor,
                                           const std::vector<Eigen::Vector2d>& world_points,
                                           const std::optional<SensorView>& view = std::nullopt);

  const std::vector<TrackedObject>& objects() const { return now_.objects; }
  // The newest scan's points that are not part of a moving object (walls included): what stays where it is.
  const std::vector<Eigen::Vector2d>& static_points() const { return now_.static_points; }
  const Surroundings& surroundings() const { return now_; }
  void Clear();

 private:
  struct Point {
    Eigen::Vector2d xy;
    double t;
  };
  // One cluster seen in the newest scan.
  struct Cluster {
    Eigen::Vector2d position;
    std::vector<Eigen::Vector2d> newest;  // its points in the newest scan
    double radius_m = 0.0;
    int points = 0;
    std::optional<Eigen::Vector2d> velocity;  // lower/upper-half estimate, when the cluster spans enough time
    void Measure();                           // position and radius_m from `newest` (not empty)
  };
  struct Sighting {
    double stamp_s;
    Eigen::Vector2d position;
    double radius_m;
    bool whole;  // not partly hidden: its extent is at least partial_fraction of the widest recent whole one
  };
  struct Track {
    int id;
    Eigen::Vector2d position;
    Eigen::Vector2d velocity;
    double radius_m;
    int points;
    double stamp_s;                                                // of position
    double last_seen_s;                                            // alone in a cluster
    std::deque<Sighting> seen;                                     // when seen alone, oldest first
    double maneuver_s = -std::numeric_limits<double>::infinity();  // when its velocity last changed abruptly
    Eigen::Vector2d walked = Eigen::Vector2d::Zero();              // its last velocity at walking speed
    bool out_of_view = false;  // moving, and predicted outside the sensor's view at the last scan
    double out_of_view_s = -std::numeric_limits<double>::infinity();  // the last scan at which it was
  };
  struct WalkEnd {
    Eigen::Vector2d position;  // the farthest the track got before turning
    Eigen::Vector2d heading;   // unit: the way it walked into the end
    double stamp_s;
    int track;  // whose turn it was
  };
  // Records the track's sighting at stamp_s and updates its velocity from its own positions and the cluster's.
  void See(Track& track, double stamp_s, const Cluster& cluster) const;
  // Gives each of the tracks `sharing` (indices into tracks_) its own part of a cluster they share.
  void SplitAmong(double stamp_s, const Cluster& cluster, const std::vector<std::size_t>& sharing);
  // Remembers the end of a walk when the track has just turned round.
  void NoteTurn(Track& track, double stamp_s);
  std::optional<Eigen::Vector2d> WalkEndAhead(const Track& track) const;
  bool OnMap(const Eigen::Vector2d& p) const;
  std::vector<Cluster> FindClusters() const;
  // `view`: what the newest scan covers, when not all round.
  void UpdateTracks(double stamp_s, const std::vector<Cluster>& clusters, const std::optional<SensorView>& view);

  MovingObjectOptions options_;
  std::shared_ptr<const OccupancyGrid> map_;
  int map_reach_ = 0;
  struct Scan {
    double stamp_s;
    std::vector<Point> points;
  };
  std::deque<Scan> scans_;  // oldest first
  double newest_stamp_s_ = 0.0;
  std::vector<Eigen::Vector2d> newest_on_map_;  // the newest scan's points on the map's walls
  Surroundings now_;
  std::vector<Track> tracks_;
  std::vector<WalkEnd> walk_ends_;  // oldest first
  int next_id_ = 1;
};

}  // namespace corridor::nav
