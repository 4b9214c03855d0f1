// The local navigator: follows the global path (PathFollower, the polar pose controller of Wang et al.) and passes
// what the map does not show with MORP-RB on the depth camera's lanes (DPoom). Each step:
//   - on the way, while the lanes ahead are clear, the path follower steers toward its look-ahead point, its speed
//     capped by what the robot can stop within;
//   - when they are not, MORP-RB takes over with the look-ahead point as its waypoint (change lane, overtake, turn
//     back), at no more than the path's speed limit. Only for what the map does not show: a dead-end on an obstacle
//     of the map the path was planned on (a wall the path turns before, a mapped speck it passes) is the path's
//     business; swerving for it takes the robot off its path, in cluttered maps into space the planner would not
//     enter. It still caps the speed, and the memory still guards against it;
//   - the final approach is the polar controller's alone (MORP-RB would swerve around the goal's own
//     surroundings), still capped by the free distance ahead;
//   - a robot pushed (or swerved) far from the path asks for a new one; so does one that has made no headway for a
//     while (boxed in by what the map does not show: dithering between two obstacles the path passes between), for
//     paths planned round what it remembered then (Blocking, AddPointCost), the first of which it turns to on the
//     spot before following it;
//   - every command is checked against a short memory of dead-ends and the map's obstacles
//     (nav/safety/obstacle_memory.h), so that turning back to the path does not sweep into an obstacle that has
//     left the camera's view, nor into a mapped one it never saw. When the memory had to
//     refuse the way toward the path, the robot drives on straight (detour_m) before heading for the path again;
//     otherwise it would turn back toward the hidden obstacle at once, be refused again, and dither in place. Not
//     when the map alone refused it: the path keeps clear of the map, the follower's arc cut a corner of it;
//   - with a laser, moving objects tracked around the robot (nav/tracking) are predicted, and a command that would
//     meet one is replaced by a way out of its path (nav/policy/evasion.h): people who do not see the robot walk
//     into it from the sides and from behind, where the camera cannot see.
// Pure logic: the caller supplies the pose, this frame's lanes and the time step.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "nav/ground/morp.h"
#include "nav/planner/costmap.h"
#include "nav/policy/demonstrations.h"
#include "nav/policy/evasion.h"
#include "nav/policy/flmc.h"
#include "nav/policy/local_policy.h"
#include "nav/policy/morp_il.h"
#include "nav/policy/morp_rb.h"
#include "nav/policy/path_follower.h"
#include "nav/policy/takiguchi.h"
#include "nav/safety/obstacle_memory.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct LocalNavigatorOptions {
  FollowerOptions follower;
  MorpRbOptions avoid;
  ObstacleMemoryOptions memory;
  EvasionOptions evade;
  // MORP-RB steers on the lanes within this of the centre line (the footprint and a margin); the memory keeps
  // every lane's dead-end.
  double corridor_half_width_m = 0.3;
  double mapped_tolerance_m = 0.15;  // a dead-end this near an obstacle of the path's map is the map's
  // A lane blind (too near something to measure) with a map obstacle within this ahead of the robot's centre on
  // its line is the map's too: the camera cannot see a mapped speck the robot stands close to.
  double blind_mapped_m = 0.6;
  // On the final approach, a goal this near that the robot cannot drive nearer to (something right in front, seen
  // or too near to see) counts as reached: it turns to the goal's heading there instead of waiting.
  double blocked_arrival_m = 0.05;
  double replan_distance_m = 1.0;  // farther than this from the path: plan again from where the robot is
  // Where people's ways are known (nav/tracking/traffic_map.h), the path is planned again this often and taken
  // when it goes another way (0: never). Used by whoever plans: the mission node, the scenario runner.
  double reroute_s = 2.0;
  double reroute_look_m = 4.0;       // a new path is taken when, within this much of it, it strays from the
  double reroute_tolerance_m = 0.4;  // current one by more than this: another way, not the same from a new start
  double detour_m = 0.6;
  // No headway (never farther than stuck_distance_m from where it was) for stuck_s: the way is blocked (0: never).
  double stuck_s = 10.0;
  double stuck_distance_m = 0.3;
  // Paths planned round what blocked the robot (for blocked_hold_s after, the memory's keep_s: reroutes too, lest
  // they lead back through it) add blocked_cost to the cells within blocked_radius_m of each point it remembered
  // then (the footprint and the memory's margin, and a cell): see AddPointCost.
  double blocked_radius_m = 0.4;
  double blocked_cost = 20.0;
  double blocked_hold_s = 30.0;
  // The first path after a blocked report is turned to on the spot until the robot heads within reorient_done_rad of
  // it (or for reorient_max_s at most): one that leads back out of a gap too narrow to pass is followed, instead of
  // MORP-RB turning toward the free lanes in the gap, back and forth.
  double reorient_done_rad = 0.35;
  double reorient_max_s = 10.0;
  // MORP-IL (morp_il.h) in MORP-RB's place: its network gives the command wherever MORP-RB and the path follower
  // would (not while turning to a new path on the spot, nor on the final approach, which stays the pose
  // controller's), capped like theirs by the path's speed and what the robot can stop within. Null: MORP-RB.
  std::shared_ptr<const Mlp> learned;
  MorpIlOptions il;
  // Training only: records every step's input and the rules' command, and mixes who drives (Demonstrations).
  std::shared_ptr<Demonstrations> teach;
  // Takiguchi's direction network (takiguchi.h) in MORP-RB's place instead, where MORP-IL's would be: it picks a
  // heading or stop from what the tracker shows round the robot, and the heading controller drives. While training
  // (`teach`), every step is labelled by the safe-direction expert, which drives alone without a network. Its
  // commands are capped by the path's speed and what the robot can stop within, and guarded by the obstacle memory;
  // evasion does not replace them (finding a way past people is what the network is for).
  bool direction_policy = false;
  std::shared_ptr<const Mlp> direction;
  TakiguchiOptions takiguchi;
  SafeDirectionOptions safe;
  // ASNS's fuzzy controllers (flmc.h) in MORP-RB's place instead: motion toward the path's lookahead point with the
  // distance left to the goal, obstacle avoidance from the cones ahead (the lanes' dead-ends and the obstacle memory),
  // rotation on the spot near a waypoint; to within flmc.stop_within_m of the goal, after which the pose controller
  // turns the robot to the goal's heading. Capped like the others by the path's speed and what the robot can stop
  // within, guarded by the memory; evasion of people stays.
  bool fuzzy_policy = false;
  FlmcOptions flmc;
};

class LocalNavigator final : public LocalPolicy {
 public:
  explicit LocalNavigator(const LocalNavigatorOptions& options);  // throws std::invalid_argument for bad gains

  // `map`, when not null, is the costmap the path was planned on (see mapped_tolerance_m); the memory keeps clear
  // of its obstacles too.
  void SetPath(std::vector<Waypoint> path, std::shared_ptr<const Costmap> map = nullptr) override;
  // The map changed under a path that still stands (see SetPath).
  void SetMap(std::shared_ptr<const Costmap> map) override { memory_.SetMap(std::move(map)); }
  // The bumper is pressed: what touched the front is remembered, so that the next commands turn away from it.
  void Touched(const Pose2& robot, bool backing) override { memory_.Touched(robot, backing); }
  // The frame's depth scan, before Update with its lanes: what the camera saw beside the lanes is remembered too
  // (ObstacleMemory::See).
  void See(const Pose2& robot, const std::vector<Eigen::Vector2d>& scan, const SensorView& view) {
    memory_.See(robot, scan, view);
  }
  const std::vector<Waypoint>& path() const override { return follower_.path(); }
  // What blocked the robot (world frame: the points it remembered seeing when it last reported `blocked`), for
  // blocked_hold_s after; empty otherwise. Every path planned meanwhile should go round them (AddPointCost).
  const std::vector<Eigen::Vector2d>& Blocking() const override { return blocking_; }
  // What the obstacle memory holds now (world frame), for traces.
  std::vector<Eigen::Vector2d> Remembered() const override { return memory_.Points(); }
  void Clear() override { follower_.Clear(); }
  const LocalNavigatorOptions& options() const { return options_; }

  // One step from the robot's pose and this frame's lanes (empty: nothing seen, the robot stops). dt_s is the time
  // since the previous step; speed_limit_mps caps the whole mission. `around` (may be null: no laser, or its
  // scans are stale) is what the laser shows around the robot, in the same frame as `robot`.
  LocalStep Update(const Pose2& robot, const std::vector<LaneResult>& lanes, double speed_limit_mps, double dt_s,
                   const Surroundings* around = nullptr);
  // The frame's depth scan (See), then its lanes (Update above).
  LocalStep Update(const Pose2& robot, const FrameView& frame, double speed_limit_mps, double dt_s,
                   const Surroundings* around) override;

 private:
  // The command MORP-IL gives (or the rules' `expert`, while training lets them drive), recording the step when
  // training; `v_free`: what the robot can stop within.
  Twist2 Imitate(const Pose2& robot, const std::vector<LaneResult>& lanes, const FollowStep& follow,
                 const Twist2& expert, double v_free, LocalStep& step);
  // The command of Takiguchi's network (or of the expert, while training lets it drive), recording the step when
  // training.
  Twist2 Direct(const Pose2& robot, const Surroundings* around, const FollowStep& follow, double v_free,
                LocalStep& step);
  // The fuzzy controllers' command (fuzzy_policy).
  Twist2 Fuzzy(const Pose2& robot, const std::vector<LaneResult>& lanes, const FollowStep& follow, double v_free,
               LocalStep& step);
  // Replaces the step's twist when a tracked moving object would meet the robot on it; `target`: where the robot
  // is heading (world frame).
  void Evade(const Pose2& robot, const Eigen::Vector2d& target, const Surroundings* around, LocalStep& step);
  // True when the lane's dead-end (seen from `robot`) lies on an obstacle of the path's map.
  bool OnMap(const Pose2& robot, const LaneResult& lane) const;

  LocalNavigatorOptions options_;
  PathFollower follower_;
  MorpRb avoid_;
  ObstacleMemory memory_;
  Evasion evade_;
  std::vector<LaneResult> ahead_;  // this frame's lanes in the corridor
  std::vector<LaneResult> seen_;   // all of them, the map's own obstacles taken out (MORP-IL's)
  MorpIlFeatures features_;
  std::unique_ptr<Flmc> flmc_;  // fuzzy_policy
  Twist2 last_command_;         // the step before's
  double detour_left_m_ = 0.0;
  double last_speed_mps_ = 0.0;
  std::optional<Eigen::Vector2d> headway_from_;  // where the robot was when it last made headway
  double without_headway_s_ = 0.0;
  std::vector<Eigen::Vector2d> blocking_;
  double blocked_s_ = 0.0;  // since blocking_ was taken
  bool reorient_next_path_ = false;
  double reorient_s_ = -1.0;  // turning to a new path on the spot for this long; negative: not turning
};

}  // namespace corridor::nav
