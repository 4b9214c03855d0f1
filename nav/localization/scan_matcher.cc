#include "nav/localization/scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

namespace corridor::nav {
namespace {

// The angle step that moves the farthest point by about one cell (Olson 2009, eq. 6 in Hess et al.).
double AngularStep(const HitField& grid, std::span<const Eigen::Vector2f> points) {
  double far = 0.0;
  for (const Eigen::Vector2f& p : points) far = std::max(far, static_cast<double>(p.norm()));
  const double r = grid.resolution_m();
  if (far < r) return 0.05;
  return std::acos(std::clamp(1.0 - r * r / (2.0 * far * far), -1.0, 1.0));
}

using Grid = ceres::Grid2D<float, 1>;
using Interpolator = ceres::BiCubicInterpolator<Grid>;

// One residual per point: 1 - the grid's match value at the point moved by the pose (x, y, yaw).
class OccupiedSpaceCost {
 public:
  OccupiedSpaceCost(const HitField& grid, std::span<const Eigen::Vector2f> points, double weight)
      : grid_(grid.match_values().data(), 0, grid.height(), 0, grid.width()),
        interpolator_(grid_),
        points_(points),
        min_corner_(grid.min_corner()),
        resolution_m_(grid.resolution_m()),
        weight_(weight) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    const T c = ceres::cos(pose[2]);
    const T s = ceres::sin(pose[2]);
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const T px = T(static_cast<double>(points_[i].x()));
      const T py = T(static_cast<double>(points_[i].y()));
      const T x = c * px - s * py + pose[0];
      const T y = s * px + c * py + pose[1];
      const T col = (x - min_corner_.x()) / resolution_m_ - 0.5;
      const T row = (y - min_corner_.y()) / resolution_m_ - 0.5;
      T p;
      interpolator_.Evaluate(row, col, &p);
      residual[i] = weight_ * (1.0 - p);
    }
    return true;
  }

 private:
  Grid grid_;
  Interpolator interpolator_;
  std::span<const Eigen::Vector2f> points_;
  Eigen::Vector2d min_corner_;
  double resolution_m_;
  double weight_;
};

struct PriorCost {
  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    residual[0] = translation_weight * (pose[0] - x);
    residual[1] = translation_weight * (pose[1] - y);
    // The heading prior's difference, wrapped to (-pi, pi].
    const T d = pose[2] - yaw;
    residual[2] = rotation_weight * ceres::atan2(ceres::sin(d), ceres::cos(d));
    return true;
  }
  double x, y, yaw, translation_weight, rotation_weight;
};

}  // namespace

double ScoreAt(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& pose) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (const Eigen::Vector2f& p : points) {
    const CellIndex c = grid.CellOf(pose.Transform(p.cast<double>()));
    sum += grid.match_value(c.x, c.y);
  }
  return sum / static_cast<double>(points.size());
}

ScanMatch CorrelativeMatch(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& guess,
                           const SearchWindow& window) {
  ScanMatch best{guess, ScoreAt(grid, points, guess)};
  if (points.empty() || grid.empty()) return best;
  const double r = grid.resolution_m();
  // Translations by whole cells move every point's cell by the same offset: each angle's points are put in their
  // cells once, and a candidate costs one lookup per point (Hess et al., section V.B: "discretized scans").
  const int cells_per_step = std::max(1, static_cast<int>(std::lround(window.linear_step_m / r)));
  const double linear_step = cells_per_step * r;
  const double angular_step = window.angular_step_rad > 0.0 ? window.angular_step_rad : AngularStep(grid, points);
  const int n_linear = static_cast<int>(std::ceil(window.linear_m / linear_step));
  const int n_angular = static_cast<int>(std::ceil(window.angular_rad / angular_step));
  std::vector<CellIndex> cells(points.size());
  for (int a = -n_angular; a <= n_angular; ++a) {
    const double yaw = guess.yaw_rad + a * angular_step;
    const double c = std::cos(yaw);
    const double s = std::sin(yaw);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double px = points[i].x();
      const double py = points[i].y();
      cells[i] = grid.CellOf({c * px - s * py + guess.x_m, s * px + c * py + guess.y_m});
    }
    const double a2 = (a * angular_step) * (a * angular_step);
    for (int iy = -n_linear; iy <= n_linear; ++iy) {
      for (int ix = -n_linear; ix <= n_linear; ++ix) {
        const int dx = ix * cells_per_step;
        const int dy = iy * cells_per_step;
        double sum = 0.0;
        for (const CellIndex& cell : cells) sum += grid.match_value(cell.x + dx, cell.y + dy);
        const double d2 = (ix * ix + iy * iy) * linear_step * linear_step;
        const double score = sum / static_cast<double>(points.size()) *
                             std::exp(-(window.translation_cost * d2 + window.rotation_cost * a2));
        if (score > best.score) {
          best = {Pose2{guess.x_m + ix * linear_step, guess.y_m + iy * linear_step, WrapAngle(yaw)}, score};
        }
      }
    }
  }
  return best;
}

Pose2 RefineMatch(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& start, const Pose2& prior,
                  const RefineOptions& options) {
  if (points.empty() || grid.empty()) return start;
  double pose[3] = {start.x_m, start.y_m, start.yaw_rad};
  ceres::Problem problem;
  const double weight = options.occupied_weight / std::sqrt(static_cast<double>(points.size()));
  auto* occupied = new ceres::AutoDiffCostFunction<OccupiedSpaceCost, ceres::DYNAMIC, 3>(
      new OccupiedSpaceCost(grid, points, weight), static_cast<int>(points.size()));
  problem.AddResidualBlock(occupied, nullptr, pose);
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<PriorCost, 3, 3>(
          new PriorCost{prior.x_m, prior.y_m, prior.yaw_rad, options.translation_weight, options.rotation_weight}),
      nullptr, pose);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  return {pose[0], pose[1], WrapAngle(pose[2])};
}

}  // namespace corridor::nav
