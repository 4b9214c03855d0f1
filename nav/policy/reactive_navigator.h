// The voxel-reactive local policy, the comparison pipeline of DPoom's evaluation: the path follower gives the point to
// steer to (and says when the robot has strayed from the path), and a memoryless reactive controller on the voxel
// front end's obstacle points (reactive.h, voxel_obstacles.h) gives the command. No lanes, no memory, no evasion.
#pragma once

#include "nav/policy/local_policy.h"
#include "nav/policy/path_follower.h"
#include "nav/policy/reactive.h"

namespace corridor::nav {

class ReactiveNavigator final : public LocalPolicy {
 public:
  // `replan_distance_m`: farther than this from the path, the step asks for a new one.
  ReactiveNavigator(const FollowerOptions& follower, const ReactiveOptions& reactive, double replan_distance_m);

  void SetPath(std::vector<Waypoint> path, std::shared_ptr<const Costmap> map) override;
  void SetMap(std::shared_ptr<const Costmap>) override {}
  const std::vector<Waypoint>& path() const override { return follower_.path(); }
  void Clear() override { follower_.Clear(); }
  void Touched(const Pose2&, bool) override {}
  const std::vector<Eigen::Vector2d>& Blocking() const override { return none_; }
  std::vector<Eigen::Vector2d> Remembered() const override { return {}; }
  // Reads frame.obstacles only.
  LocalStep Update(const Pose2& robot, const FrameView& frame, double speed_limit_mps, double dt_s,
                   const Surroundings* around) override;

 private:
  PathFollower follower_;
  ReactiveOptions reactive_;
  double replan_distance_m_;
  std::vector<Eigen::Vector2d> none_;
};

}  // namespace corridor::nav
