// Mapping a building: graph SLAM from range scans and odometry, in the manner of Cartographer (Hess, Kohler, Rapp
// and Andor, "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016).
//
// Local SLAM: each scan is placed by odometry, then matched into the current submap (CorrelativeMatch in a small
// window, RefineMatch with the odometry's pose as prior); scans that moved enough are inserted into the two active
// submaps, which overlap by half, so that there is always a submap with half its scans to match against. Global SLAM:
// scans and submaps are nodes of a pose graph tied by where each scan lies in its submaps and by the local SLAM's
// motion from one scan to the next; every few scans, the scan is
// searched for in the finished submaps near its estimate (BranchAndBoundMatcher), and a match becomes a loop closure
// constraint; the graph is optimized (PoseGraph) when new loop closures came in.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "nav/localization/branch_and_bound.h"
#include "nav/localization/hit_field.h"
#include "nav/localization/pose_graph.h"
#include "nav/localization/range_scan.h"
#include "nav/localization/scan_matcher.h"
#include "nav/map/log_odds_grid.h"

namespace corridor::nav {

struct GraphSlamOptions {
  HitFieldOptions grid;
  double match_voxel_m = 0.05;       // scan points are thinned to one per square this size before matching
  int scans_per_submap = 40;         // inserted scans that finish a submap
  double insert_distance_m = 0.1;    // a scan is inserted once the robot moved this far or turned
  double insert_angle_rad = 0.0175;  // this much since the last inserted scan
  SearchWindow local_window{0.15, 0.12};
  // The refinement pulls towards the odometry's prediction as hard as the odometry is precise over the step: weight =
  // prior_scale / sigma, sigma = floor + per-unit noise x the step's length (or turn). A short step keeps the
  // odometry's shape, which over centimetres is better than any match; a long one leaves the scan to the match.
  RefineOptions local_refine{1.0, 1.0, 1.0, 20};
  double odometry_sigma_floor_m = 0.01;
  double odometry_sigma_per_m = 0.05;
  double odometry_sigma_floor_rad = 0.01;
  double odometry_sigma_per_rad = 0.035;
  double prior_translation_scale = 0.07;
  double prior_rotation_scale = 0.03;
  // Loop closure.
  // A scan is searched for in the finished submaps when it is at least the n-th since the last one searched and the
  // robot travelled loop_search_travel_m since; in at most loop_max_submaps of them, the nearest whose origin is
  // within loop_search_radius_m of the scan's estimate.
  int loop_closure_every = 3;
  double loop_search_travel_m = 0.3;
  int loop_max_submaps = 6;
  double loop_search_radius_m = 10.0;
  double loop_voxel_m = 0.1;  // the scan's points are thinned further for the search
  SearchWindow loop_window{3.0, 0.3};
  double loop_min_score = 0.6;
  RefineOptions loop_refine{1.0, 1.0, 1.0, 20};
  int optimize_every = 30;  // scans between optimizations (only when loop closures came in)
  // Pose graph weights (Cartographer's): where a scan lies in its submaps (weak: submaps may bend), the local SLAM's
  // motion between consecutive scans (strong: local SLAM is accurate over short distances), loop closures (robust).
  double submap_translation_weight = 5e2;
  double submap_rotation_weight = 1.6e3;
  double motion_translation_weight = 1e5;
  double motion_rotation_weight = 1e5;
  double loop_translation_weight = 1.1e4;
  double loop_rotation_weight = 1e5;
  PoseGraphOptions graph{10.0, 50};
};

struct GraphSlamStats {
  int scans = 0;
  int inserted = 0;
  int submaps = 0;
  int loop_searches = 0;
  int loop_closures = 0;
  int optimizations = 0;
};

// How a map built from scans is rendered: a cell the beams crossed more often than they ended in is free, even if one
// beam crossed it once (far from the robot, beams are sparse: the robot saw through it all the same, and exploration
// needs to know).
inline LogOddsOptions RenderedMapOptions() {
  LogOddsOptions options;
  options.free_below = 0.45;
  return options;
}

class GraphSlam {
 public:
  // `start`: the first scan's pose in the map frame (the origin by default; where the robot is in an older map of the
  // same building, for a new map that lines up with the old one's zones and places).
  explicit GraphSlam(const GraphSlamOptions& options = {}, const Pose2& start = {});

  // Adds a scan taken with the robot at `odom_pose` in the odometry's frame (any frame in which the odometry is
  // continuous). Returns the scan's pose in the map frame.
  Pose2 AddScan(const RangeScan& scan, const Pose2& odom_pose);
  // Optimizes once more with every loop closure found: call after the last scan.
  void Finish();

  // The map-frame pose of every scan added, in order.
  std::vector<Pose2> Trajectory() const;
  // The inserted scans rendered at their optimized poses into a log-odds grid (map_server's conventions).
  OccupancyGrid RenderMap(double resolution_m, const LogOddsOptions& options = RenderedMapOptions()) const;
  const GraphSlamStats& stats() const { return stats_; }

 private:
  struct Submap {
    HitField grid;
    Pose2 local_origin;  // local SLAM frame
    int node = 0;        // pose graph node
    int inserted = 0;
    std::unique_ptr<BranchAndBoundMatcher> matcher;  // built when first searched, once finished
  };
  struct Scan {
    int node = 0;
    bool inserted = false;
    RangeScan range;                      // kept for inserted scans (the map is rendered from them)
    std::vector<Eigen::Vector2f> points;  // thinned hits (match_voxel_m)
  };

  Pose2 LocalToGlobal(const Pose2& local) const { return global_T_local_ * local; }
  void SearchLoopClosures(const Scan& scan, const Pose2& global_estimate);
  void Optimize();

  GraphSlamOptions options_;
  PoseGraph graph_;
  std::vector<std::unique_ptr<Submap>> submaps_;
  std::vector<int> active_;  // indices into submaps_, oldest first
  std::vector<Scan> scans_;
  std::optional<Pose2> last_odom_;  // at the last scan
  Pose2 last_local_;                // of the last scan added
  std::optional<Pose2> last_inserted_;
  Pose2 global_T_local_;
  bool new_loop_closures_ = false;
  int since_loop_search_ = 0;  // scans
  double travel_since_search_m_ = 0.0;
  int since_optimized_ = 0;
  GraphSlamStats stats_;
};

// Scans rendered at their poses (map frame) into a log-odds grid that just holds them, thresholded into map_server's
// conventions. Requires a pose per scan (std::invalid_argument).
OccupancyGrid RenderScans(std::span<const RangeScan* const> scans, std::span<const Pose2> poses, double resolution_m,
                          const LogOddsOptions& options = RenderedMapOptions());

}  // namespace corridor::nav
