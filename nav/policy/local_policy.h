// The local policy: what a mission drives with between the global path and the command gate, once per depth frame.
// Two are built in, chosen by configuration (mission.policy):
//   - morp-rb: corridor's local navigator (local_navigator.h): the path follower, MORP-RB on MORP's lanes, the
//     obstacle memory fed with the frame's depth scan, and evasion of tracked moving objects;
//   - voxel-reactive: the comparison pipeline of DPoom's evaluation (reactive_navigator.h): the path follower's
//     target and a memoryless reactive controller on the obstacle points of a voxel-grid front end;
//   - morp-il: the local navigator with MORP-IL's network (morp_il.h) in MORP-RB's place;
//   - takiguchi: the local navigator with Takiguchi's direction network (takiguchi.h) in MORP-RB's place.
// The ground node makes what the configured policy reads from each frame (FrameView).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/sensor_view.h"
#include "nav/ground/morp.h"
#include "nav/planner/costmap.h"
#include "nav/planner/planner.h"
#include "nav/policy/morp_rb.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

enum class LocalPolicyKind { kMorpRb, kVoxelReactive, kMorpIl, kTakiguchi, kFlmc };
const char* ToString(LocalPolicyKind kind);
std::optional<LocalPolicyKind> ParseLocalPolicy(const std::string& name);

// What one depth frame shows, in the base frame: MORP's lanes and the frame's depth scan with the floor it covers
// (morp-rb), or a voxel front end's obstacle points (voxel-reactive). Null: the frame has none. What they point to
// must outlive the Update they go to.
struct FrameView {
  const std::vector<LaneResult>* lanes = nullptr;
  const std::vector<Eigen::Vector2d>* scan = nullptr;
  SensorView scan_view;
  const std::vector<Eigen::Vector2f>* obstacles = nullptr;
};

struct LocalStep {
  Twist2 twist;
  bool done = false;
  bool replan = false;   // strayed from the path: the caller should plan again (the twist is zero
                         // unless it evades someone)
  bool blocked = false;  // no headway for stuck_s: the caller should plan again round Blocking()
                         // (the twist is this step's as usual)
  double remaining_m = 0.0;
  MorpRbMode mode = MorpRbMode::kFollow;
  bool avoiding = false;   // MORP-RB, not the path follower, chose the twist
  bool guarded = false;    // the obstacle memory replaced the chosen twist
  bool evading = false;    // a moving object's predicted path did
  bool learned = false;    // MORP-IL's or Takiguchi's network chose the twist
  double nearest_m = 0.0;  // the nearest dead-end ahead
};

class LocalPolicy {
 public:
  LocalPolicy() = default;
  LocalPolicy(const LocalPolicy&) = delete;
  LocalPolicy& operator=(const LocalPolicy&) = delete;
  virtual ~LocalPolicy() = default;

  // A new path; `map`, when not null, is the costmap it was planned on.
  virtual void SetPath(std::vector<Waypoint> path, std::shared_ptr<const Costmap> map) = 0;
  // The map changed under a path that still stands.
  virtual void SetMap(std::shared_ptr<const Costmap> map) = 0;
  virtual const std::vector<Waypoint>& path() const = 0;
  bool has_path() const { return !path().empty(); }
  virtual void Clear() = 0;
  // The bumper was pressed, driving forward or backing.
  virtual void Touched(const Pose2& robot, bool backing) = 0;
  // What blocked the robot when it last reported `blocked` (world frame), for plans to go round (AddPointCost).
  virtual const std::vector<Eigen::Vector2d>& Blocking() const = 0;
  // What the policy remembers of obstacles now (world frame), for traces and the console.
  virtual std::vector<Eigen::Vector2d> Remembered() const = 0;

  // One step from the robot's pose and this frame. dt_s: since the previous step; speed_limit_mps caps the whole
  // mission; `around` (may be null) is what the tracker shows around the robot, in the frame of `robot`.
  virtual LocalStep Update(const Pose2& robot, const FrameView& frame, double speed_limit_mps, double dt_s,
                           const Surroundings* around) = 0;
};

}  // namespace corridor::nav
