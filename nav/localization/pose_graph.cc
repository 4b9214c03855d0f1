#include "nav/localization/pose_graph.h"

#include <stdexcept>
#include <string>

#include <ceres/ceres.h>

namespace corridor::nav {
namespace {

struct RelativePoseCost {
  template <typename T>
  bool operator()(const T* const a, const T* const b, T* residual) const {
    const T c = ceres::cos(a[2]);
    const T s = ceres::sin(a[2]);
    const T dx = b[0] - a[0];
    const T dy = b[1] - a[1];
    residual[0] = translation_weight * (c * dx + s * dy - measured.x_m);
    residual[1] = translation_weight * (-s * dx + c * dy - measured.y_m);
    const T d = b[2] - a[2] - measured.yaw_rad;
    residual[2] = rotation_weight * ceres::atan2(ceres::sin(d), ceres::cos(d));
    return true;
  }
  Pose2 measured;
  double translation_weight;
  double rotation_weight;
};

}  // namespace

int PoseGraph::AddNode(const Pose2& initial) {
  poses_.push_back({initial.x_m, initial.y_m, initial.yaw_rad});
  return size() - 1;
}

void PoseGraph::AddConstraint(const PoseConstraint& constraint) {
  if (constraint.from < 0 || constraint.to < 0 || constraint.from >= size() || constraint.to >= size()) {
    throw std::out_of_range("PoseGraph: a constraint between nodes " + std::to_string(constraint.from) + " and " +
                            std::to_string(constraint.to) + " of " + std::to_string(size()));
  }
  constraints_.push_back(constraint);
}

int PoseGraph::Optimize() {
  if (constraints_.empty()) return 0;
  ceres::Problem problem;
  for (const PoseConstraint& k : constraints_) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseCost, 3, 3, 3>(
        new RelativePoseCost{k.from_T_to, k.translation_weight, k.rotation_weight});
    ceres::LossFunction* loss = k.robust ? new ceres::HuberLoss(options_.huber_scale) : nullptr;
    problem.AddResidualBlock(cost, loss, poses_[k.from].data(), poses_[k.to].data());
  }
  if (problem.HasParameterBlock(poses_[0].data())) problem.SetParameterBlockConstant(poses_[0].data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = options_.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  for (auto& p : poses_) p[2] = WrapAngle(p[2]);
  return static_cast<int>(summary.iterations.size());
}

}  // namespace corridor::nav
