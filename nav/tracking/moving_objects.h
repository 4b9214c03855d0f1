// Moving objects from accumulated laser scans (Takiguchi et al.): the last few scans are stacked in the world
// frame with time as a third axis, so that a walking person leaves a slanted tube of points and a standing object
// a vertical one; the tubes are found by Euclidean clustering in (x, y, t * time_scale), and each cluster's
// velocity is the displacement between the centroids of its lower (older) and upper (newer) halves divided by
// the time between them.
//
// corridor's additions: points on the map's walls are dropped before clustering (they are not objects to
// track), and each object carries the newest scan's extent, so that a caller can keep clear of it.
//
// Clustering is written here (a uniform grid with union-find, linear in the number of points) rather than taken
// from OpenCV: cv::partition compares every pair, which at a few thousand points costs milliseconds per scan on a
// weak board; see docs/design.md.
#pragma once

#include <deque>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
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
};

struct TrackedObject {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // world frame: centroid of the newest scan's points
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // world frame, m/s; zero when not moving
  double radius_m = 0.0;             // the newest scan's points' largest distance from `position`
  bool moving = false;
  int points = 0;                    // over the whole window
};

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
  // first (a clock reset or a replayed log). Returns the objects seen in the newest scan.
  const std::vector<TrackedObject>& Update(double stamp_s, const Eigen::Vector2d& sensor,
                                           const std::vector<Eigen::Vector2d>& world_points);

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
  bool OnMap(const Eigen::Vector2d& p) const;
  void Cluster();

  MovingObjectOptions options_;
  std::shared_ptr<const OccupancyGrid> map_;
  int map_reach_ = 0;
  std::deque<std::vector<Point>> scans_;  // oldest first
  double newest_stamp_s_ = 0.0;
  std::vector<Eigen::Vector2d> newest_all_;
  Surroundings now_;
};

}  // namespace corridor::nav
