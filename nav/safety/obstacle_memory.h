// A short memory of what the depth camera saw, for the blind sides of a narrow camera. MORP's dead-ends are kept
// in the world frame for a few seconds; before a command goes out, the robot's footprint is swept along the arc it
// would drive for a short horizon, and a command that would bring it into a remembered obstacle is replaced by the
// nearest safe one among arcs that bend away (as a dynamic-window check would), turning in place, and stopping.
//
// Without it, a robot that has just passed an obstacle (now beside it, out of the camera's 85-degree view) turns back
// toward its path and into the obstacle's side. This is corridor's addition to MORP-RB; the paper's policy sees only
// the current frame.
//
// The map's own obstacles are known without being seen: with a costmap set, a sweep that closes in on them (its
// clearance field, nearer than robot_radius_m + map_margin_m) is refused the same way, so that a turn does not
// swing the robot into a mapped speck or into unknown space beside it; a robot already that near (leaving the band, or
// an island among unknown specks, the way a plan gives) is held only off the walls the map knows: unknown specks are
// not walls, and what the camera sees there is remembered. What the bumper touched is remembered like a dead-end
// (Touched).
//
// The lanes look straight ahead, so of an obstacle the robot passes they sample only the face toward it: the side it
// passes beside was never in a lane (a 0.5 m cylinder passed on the left showed two points 0.6 m apart, and a lane
// change toward it crept the footprint into the unsampled arc between them, in a scenario run). The depth camera sees
// more than the lanes: with See, each frame's depth scan (the nearest point of each column, nav/ground/depth_scan.h)
// is remembered too, and forgotten when a later scan sees past it.
//
// Even so, the part of an obstacle that comes beside the robot as it turns round it may never have been in view
// (traced in docs/benchmarks.md: a learned policy curving round a 1 m cylinder touched its unseen side 3 cm from where
// the samples' line went on). Within beside_m of touching what it remembers the robot must draw away.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/geometry/sensor_view.h"
#include "nav/ground/morp.h"
#include "nav/planner/astar.h"
#include "nav/planner/costmap.h"

namespace corridor::nav {

struct ObstacleMemoryOptions {
  // A dead-end is forgotten when a lane later sees free floor past it (a person walked away), a scan point when a
  // later scan sees past it (See), either when the robot is farther from it than keep_radius_m, and at the latest
  // keep_s after it was seen.
  double keep_s = 30.0;
  double keep_radius_m = 1.5;
  double clear_from_m = 0.6;  // lanes see the floor from this forward distance: only beyond it can they clear
  double lane_half_width_m = 0.05;
  double cell_m = 0.05;  // dead-ends closer than this to a remembered one replace it
  double robot_radius_m = 0.2;
  // Kept between the footprint and a remembered point: more than a lane's width, since the surface between two
  // lanes' dead-ends (never sampled) may reach that much nearer.
  double margin_m = 0.15;
  // Kept from the map's obstacles: their cells are exact (no unsampled surface between lanes), and paths keep
  // robot_radius_m plus a cell from them.
  double map_margin_m = 0.03;
  // Inside that already (crossing the inflated band on the way out a plan gave: nav/planner/astar.h), only the
  // footprint coming over a wall the map knows is refused: its unknown specks are not walls, and a robot on an island
  // of free space among them must cross to the rest. What the camera saw is then kept at approach_margin_m (the
  // planner has the robot crawl there).
  // Kept from remembered points on a goal's final approach, at a crawl: the goal itself may lie within margin_m of
  // what the camera saw around it (the planner let it be that close to the map's obstacles).
  double approach_margin_m = 0.05;
  // Within this of touching a remembered point (not on a final approach), a command may not bring the robot nearer
  // to that point at all (elsewhere within the margin, closing in is judged against the nearest point only, so that a
  // robot too near a row of points may drive along it), and a moving one must leave the robot farther from it at the
  // end of the horizon. Driving straight past it does; sliding along a row of points that near, or an arc that keeps
  // the distance (curving around an obstacle, as a learned policy swinging its heading does), is refused: the samples
  // of a round obstacle lie a few centimetres off its surface, the arcs between them nearer.
  double beside_m = 0.1;
  double horizon_s = 1.2;  // how far ahead a command is swept
  double sweep_step_s = 0.1;
  double max_turn_rps = 1.0;  // the sharpest arc the guard may substitute
  // A remembered scan point is forgotten when the scan's nearest point at its bearing (within scan_bearing_rad) lies
  // farther than it by more than scan_clear_m: seen past.
  double scan_bearing_rad = 0.0175;
  double scan_clear_m = 0.1;
  // Scan points and dead-ends this near a wall the map knows are the map's: not remembered (what is seen over its
  // unknown space is, and what the 3D map's obstacle layer put on the costmap: the camera saw that too, and its cells
  // are no more exact than the memory's points, nor hold the sides never seen).
  double scan_map_tolerance_m = 0.1;
};

class ObstacleMemory {
 public:
  explicit ObstacleMemory(const ObstacleMemoryOptions& options) : options_(options) {}

  // Ages the memory by dt_s, forgets what is too old or too far, and remembers this frame's dead-ends (lanes taken
  // at `robot`). Blind lanes are not obstacles to remember.
  void Update(const Pose2& robot, const std::vector<LaneResult>& lanes, double dt_s);

  // Remembers the same frame's depth scan (`scan`: base frame, the nearest point of each column, the image's sides
  // kept; `view`: what the scan covers, in the base frame: DepthScan::View of the identity) with the robot at
  // `robot`, and forgets the scan points remembered before that it now sees past. Points the lanes remembered are
  // left to the lanes: a scan starts above the steps the lanes see.
  void See(const Pose2& robot, const std::vector<Eigen::Vector2d>& scan, const SensorView& view);

  // `command` if its sweep stays clear of every remembered point (or moves away from them), else the clear
  // candidate nearest to it: the same or half the speed (forward or back, as commanded) on arcs bending up to
  // max_turn_rps either way; else turning in place: the way `command` turns when only the map refused it (toward
  // where the robot is going), otherwise away from the nearest point (it comes into the camera's view, which clears
  // it or confirms it). `approach`: the final approach to a goal (approach_margin_m).
  // `refused_by` (may be null) is set to what refused `command` (kNone: it passed).
  enum class Blocker { kNone, kSeen, kMap };
  Twist2 Guard(const Pose2& robot, const Twist2& command, bool approach = false, Blocker* refused_by = nullptr) const;

  // What driving `command` from `robot` for the horizon brings the footprint within the margin of, nearer than it is
  // now (by more than a few millimetres: creeping while turning on the spot is not driving into anything), or leaves
  // it no farther from a point within beside_m of touching: a remembered point (kSeen, also when the map's obstacles
  // are too), the map's obstacles alone (kMap), or nothing (kNone).
  Blocker BlockedBy(const Pose2& robot, const Twist2& command, bool approach = false) const;
  bool Blocks(const Pose2& robot, const Twist2& command, bool approach = false) const {
    return BlockedBy(robot, command, approach) != Blocker::kNone;
  }

  // The costmap of the map the robot drives in (null: none).
  void SetMap(std::shared_ptr<const Costmap> map) { map_ = std::move(map); }
  // The robot's path crosses the map's inflated band near `from` (its way out of it, as the planner gives it to a robot
  // on an island of free space or in the band: nav/planner/astar.h): within kEscapeReachM of `from` and within
  // margin_m of the band, the band's rules above hold even before the robot is in the band. nullopt: the path does not.
  void SetBandCrossing(std::optional<Eigen::Vector2d> from) { band_from_ = from; }
  const Costmap* map() const { return map_.get(); }

  // The bumper is pressed with the robot at `robot`: something is touching its front (its back when `backing`), seen
  // or not. Remembers points on that side of the footprint.
  void Touched(const Pose2& robot, bool backing = false);

  // Forgets the points within radius_m of `centre` (world frame): something known to have moved on.
  void Forget(const Eigen::Vector2d& centre, double radius_m);

  std::size_t size() const { return points_.size(); }
  // Every remembered point (world frame).
  std::vector<Eigen::Vector2d> Points() const;
  void Clear() { points_.clear(); }

 private:
  struct Point {
    Eigen::Vector2d world;
    double age_s;
    bool scanned;  // from a depth scan: a later scan may clear it
  };
  // The map's clearance at `at` (+infinity without a map or outside it).
  double MapClearance(const Eigen::Vector2d& at) const;
  // Whether `at` lies within scan_map_tolerance_m of a wall of the map itself (false without a map; the obstacle
  // layer's walls are not the map's).
  bool OnMapWall(const Eigen::Vector2d& at) const;
  void Remember(const Eigen::Vector2d& world, bool scanned = false);

  ObstacleMemoryOptions options_;
  std::vector<Point> points_;
  std::shared_ptr<const Costmap> map_;
  std::optional<Eigen::Vector2d> band_from_;
};

}  // namespace corridor::nav
