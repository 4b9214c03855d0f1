#include "nav/geometry/plane_fit.h"

#include <Eigen/SVD>

#include <cmath>
#include <vector>

namespace corridor::nav {

std::optional<std::pair<Plane, int>> RansacPlane(std::span<const Eigen::Vector3d> points,
                                                 const PlaneRansacOptions& options, std::mt19937& rng,
                                                 const std::function<bool(Plane&)>& admissible) {
  if (points.size() < 3) return std::nullopt;
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::optional<std::pair<Plane, int>> best;
  for (int it = 0; it < options.iterations; ++it) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    Plane plane{n, -n.dot(a)};
    if (admissible && !admissible(plane)) continue;
    int count = 0;
    for (const Eigen::Vector3d& p : points) count += std::abs(plane.Distance(p)) < options.inlier_m;
    if (!best || count > best->second) best.emplace(plane, count);
  }
  return best;
}

std::optional<Plane> RefinePlane(std::span<const Eigen::Vector3d> points, const Plane& plane, double inlier_m) {
  std::vector<Eigen::Vector3d> inliers;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(plane.Distance(p)) < inlier_m) {
      inliers.push_back(p);
      centroid += p;
    }
  }
  if (inliers.size() < 3) return std::nullopt;
  centroid /= static_cast<double>(inliers.size());
  Eigen::MatrixXd centred(static_cast<Eigen::Index>(inliers.size()), 3);
  for (std::size_t i = 0; i < inliers.size(); ++i) {
    centred.row(static_cast<Eigen::Index>(i)) = (inliers[i] - centroid).transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  Eigen::Vector3d n = svd.matrixV().col(2).normalized();
  if (n.dot(plane.normal) < 0.0) n = -n;
  return Plane{n, -n.dot(centroid)};
}

}  // namespace corridor::nav
