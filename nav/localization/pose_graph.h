// A pose graph over planar poses, optimized by nonlinear least squares with Ceres (Lu and Milios, "Globally
// consistent range scan alignment", 1997; the sparse pose adjustment of Konolige et al., IROS 2010; Cartographer's
// optimization problem, Hess et al., ICRA 2016, section VI). Nodes are poses in one global frame; a constraint says
// where node `to` lies seen from node `from`, with weights on its translation and rotation. Loop closures, which can
// be wrong, go through a Huber loss so that one bad match bends the graph little.
#pragma once

#include <array>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct PoseConstraint {
  int from = 0;
  int to = 0;
  Pose2 from_T_to;                  // the measured relative pose
  double translation_weight = 1.0;  // residual = weight * error (m, rad)
  double rotation_weight = 1.0;
  bool robust = false;  // a Huber loss of scale huber_scale on this constraint
};

struct PoseGraphOptions {
  double huber_scale = 1.0;
  int max_iterations = 50;
};

class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphOptions& options = {}) : options_(options) {}

  // Adds a node at an initial estimate; returns its index. The first node is held fixed (it anchors the frame).
  int AddNode(const Pose2& initial);
  // Requires both ends to be existing nodes (std::out_of_range otherwise).
  void AddConstraint(const PoseConstraint& constraint);

  // Moves the nodes to minimize the weighted constraint errors. Returns the number of iterations.
  int Optimize();

  int size() const { return static_cast<int>(poses_.size()); }
  Pose2 pose(int node) const { return {poses_[node][0], poses_[node][1], poses_[node][2]}; }
  void set_pose(int node, const Pose2& p) { poses_[node] = {p.x_m, p.y_m, p.yaw_rad}; }
  const std::vector<PoseConstraint>& constraints() const { return constraints_; }

 private:
  PoseGraphOptions options_;
  std::vector<std::array<double, 3>> poses_;
  std::vector<PoseConstraint> constraints_;
};

}  // namespace corridor::nav
