// Docking and undocking: driving the last half metre onto a charging dock with the polar pose controller
// (polar_controller.h), guided by the dock's face as the depth camera sees it, and backing off it again.
//
// A dock is a place where the robot stands to charge (its centre and heading, facing the dock) with a flat face of
// known width in front of it. A docking mission drives to the staging pose, staging_distance_m straight back from the
// docked pose, on its planned path; from there this takes over:
//   seeking      standing still until the face has been seen min_sightings times where the map puts it (within
//                search_window_m), or failing after not_seen_s;
//   approaching  the polar controller toward the docked pose as the sightings place it in the odometry frame
//                (odometry is exact enough over half a metre, localization may jump; an exponential mean of the
//                sightings, the newest weighing most), slowly, reversing when it overshoots;
//   final        closer than blind_distance_m to the face the camera sees too little of it (and nothing within its
//                minimum range): the last centimetres go on odometry alone to the pose last estimated;
//   docked       within position_tolerance_m and yaw_tolerance_rad.
// The face is found in the depth scan (one point per image column, base frame) by a search over headings near the
// expected one for the densest line, its inliers' widest contiguous run, and a width check: a person or a box in
// front of the dock is not taken for it.
//
// Pure logic: the caller hands in the time, the odometry pose and each frame's depth scan, and sends the twists.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/map/zones.h"
#include "nav/mission/mission.h"
#include "nav/planner/costmap.h"
#include "nav/policy/polar_controller.h"

namespace corridor::nav {

// The dock model the robot is built for.
struct DockGeometry {
  double width_m = 0.4;             // of the face the camera sees
  double face_distance_m = 0.21;    // from the robot's centre to the face when docked
  double staging_distance_m = 0.7;  // the staging pose stands this far straight back from the docked pose
};

// The staging pose of a dock whose docked pose is `docked` (same heading, staging_distance_m back).
Pose2 StagingPose(const Pose2& docked, const DockGeometry& dock);

// Why no mission can dock at a dock whose docked pose is `docked` on `costmap` ("its staging pose (x, y) is ..."): its
// staging pose, where docking missions go first, is off the map, in a keep-out zone, on an obstacle or unknown space,
// or closer to an obstacle than the robot's radius allows; nullopt when a mission can go there.
std::optional<std::string> DockUnreachable(const Costmap& costmap, const Pose2& docked, const DockGeometry& dock);

// A mission goal that docks at `dock` (a place of kind dock): its staging pose, then onto it.
MissionGoal DockGoal(const Place& dock, const DockGeometry& geometry);
// The goal that backs off the dock the robot stands on (at `robot`, when known) to its staging pose.
MissionGoal UndockGoal(const std::optional<Pose2>& robot, const DockGeometry& geometry);
// The dock among `places` nearest to `robot`; none when there is no dock.
std::optional<Place> NearestDock(const std::vector<Place>& places, const Eigen::Vector2d& robot);

struct DockingOptions {
  DockGeometry dock;
  PolarGains gains{.k_rho = 0.5, .k_alpha = 2.0, .k_beta = -0.8};
  double max_speed_mps = 0.1;
  double max_turn_rps = 0.6;
  double min_speed_mps = 0.01;  // slower than this the wheels do not turn: crawl at least this fast
  double position_tolerance_m = 0.003;
  double yaw_tolerance_rad = 0.0087;  // half a degree
  double blind_distance_m = 0.42;     // centre to face: nearer than this, odometry alone
  double search_window_m = 0.25;      // the face is looked for this far around where it is expected
  double width_tolerance_m = 0.05;    // a face this much narrower or wider than the dock's is not the dock
  int min_sightings = 3;
  double not_seen_s = 5.0;  // seeking this long without min_sightings: the dock is not there
  double timeout_s = 60.0;  // the whole docking
  double undock_tolerance_m = 0.03;
};

// Throws std::invalid_argument naming the bad option.
void Validate(const DockingOptions& options);

// The docked pose (base frame) of a dock face found in `scan` (base frame points) near `expected` (the docked pose,
// base frame); none when no line of about the dock's width stands there.
std::optional<Pose2> FindDockFace(const std::vector<Eigen::Vector2d>& scan, const Pose2& expected,
                                  const DockingOptions& options);

enum class DockingPhase { kSeeking, kApproaching, kFinal, kDocked, kUndocking, kUndocked, kFailed };
const char* ToString(DockingPhase phase);

struct DockingStep {
  Twist2 twist;
  DockingPhase phase = DockingPhase::kSeeking;
  bool seen = false;         // the face was found in this frame's scan
  double remaining_m = 0.0;  // to the docked (or undocked) pose
  std::string error;         // kFailed: why
  bool finished() const {
    return phase == DockingPhase::kDocked || phase == DockingPhase::kUndocked || phase == DockingPhase::kFailed;
  }
};

class Docking {
 public:
  // Docking onto a dock expected at odom_T_dock (its docked pose in the odometry frame, from the map). Throws
  // std::invalid_argument for bad options.
  static Docking Dock(const DockingOptions& options, const Pose2& odom_T_dock, double now_s);
  // Backing straight off the dock the robot stands on (at odom_T_base) to where its staging pose is.
  static Docking Undock(const DockingOptions& options, const Pose2& odom_T_base, double now_s);

  // One step at now_s with the robot at odom_T_base; `scan` is this frame's depth scan (null: no frame).
  DockingStep Update(double now_s, const Pose2& odom_T_base, const std::vector<Eigen::Vector2d>* scan);
  // Where the dock is now believed to be (odometry frame).
  Pose2 target() const { return target_; }
  int sightings() const { return sightings_; }

 private:
  Docking(const DockingOptions& options, const Pose2& target, DockingPhase phase, double now_s);
  void Sighted(const Pose2& odom_T_dock);
  DockingStep Drive(const Pose2& odom_T_base, double tolerance_m, bool turn_to_heading);

  DockingOptions options_;
  Pose2 target_;
  DockingPhase phase_;
  double started_s_;
  int sightings_ = 0;
};

// When an idle robot goes to charge: below charge_below_percent (0: never), not on its charger, with no mission under
// way, and not again within retry_s of the last time it set off (so a docking that failed is tried again later, not
// at once).
struct ChargingOptions {
  double charge_below_percent = 0.0;
  double retry_s = 300.0;
};

class ChargingPolicy {
 public:
  explicit ChargingPolicy(const ChargingOptions& options) : options_(options) {}
  // True when the robot should set off for its dock now (and then not again for retry_s).
  bool ShouldGo(double now_s, double charge, bool on_charger, bool busy);

 private:
  ChargingOptions options_;
  double last_s_ = -1e300;
};

}  // namespace corridor::nav
