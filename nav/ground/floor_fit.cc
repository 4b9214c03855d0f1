#include "nav/ground/floor_fit.h"

#include <Eigen/SVD>

#include <cmath>
#include <numbers>

namespace corridor::nav {

std::optional<FloorFit> FitFloor(const cv::Mat& depth, const PinholeCamera& camera, const FloorFitOptions& options,
                                 std::mt19937& rng) {
  const bool millimetres = depth.type() == CV_16UC1;
  std::vector<Eigen::Vector3d> points;
  for (int v = depth.rows / 2; v < depth.rows; v += options.stride_px) {
    for (int u = 0; u < depth.cols; u += options.stride_px) {
      const double d = millimetres ? depth.ptr<std::uint16_t>(v)[u] * 0.001 : depth.ptr<float>(v)[u];
      if (d > 0.0 && std::isfinite(d) && d <= options.max_range_m) points.push_back(camera.Ray(u, v) * d);
    }
  }
  if (points.size() < 30) return std::nullopt;

  const double cos_max = std::cos(options.max_normal_angle_deg * std::numbers::pi / 180.0);
  const Eigen::Vector3d up(0.0, -1.0, 0.0);  // optical frame: y points down
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  Eigen::Vector3d best_normal = up;
  double best_offset = 0.0;
  int best_count = 0;
  for (int it = 0; it < options.iterations; ++it) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    if (n.dot(up) < 0.0) n = -n;
    if (n.dot(up) < cos_max) continue;  // a wall or a table edge, not a floor
    const double offset = -n.dot(a);
    if (offset <= 0.0) continue;  // the camera must be above the plane
    int count = 0;
    for (const Eigen::Vector3d& p : points) count += std::abs(n.dot(p) + offset) < options.inlier_threshold_m;
    if (count > best_count) {
      best_count = count;
      best_normal = n;
      best_offset = offset;
    }
  }
  if (best_count < options.min_inlier_fraction * static_cast<double>(points.size())) return std::nullopt;

  // Least squares on the inliers: the plane through their centroid normal to their least-spread direction.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(best_normal.dot(p) + best_offset) < options.inlier_threshold_m) inliers.push_back(p);
  }
  for (const Eigen::Vector3d& p : inliers) centroid += p;
  centroid /= static_cast<double>(inliers.size());
  Eigen::MatrixXd centred(inliers.size(), 3);
  for (std::size_t i = 0; i < inliers.size(); ++i)
    centred.row(static_cast<Eigen::Index>(i)) = (inliers[i] - centroid).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  Eigen::Vector3d n = svd.matrixV().col(2).normalized();
  if (n.dot(up) < 0.0) n = -n;

  FloorFit fit;
  fit.normal = n;
  fit.offset = -n.dot(centroid);
  fit.camera_height_m = fit.offset;  // distance from the optical centre to the plane
  // The optical axis (0, 0, 1) makes angle asin(n . z) with the floor; pitched down, it points into the floor.
  fit.tilt_rad = -std::asin(std::clamp(n.z(), -1.0, 1.0));
  fit.roll_rad = std::atan2(n.x(), -n.y());
  fit.inliers = static_cast<int>(inliers.size());
  fit.inlier_fraction = static_cast<double>(inliers.size()) / static_cast<double>(points.size());
  return fit;
}

Eigen::Isometry3d MountingFromFloor(const FloorFit& fit, const Eigen::Isometry3d& nominal) {
  // The optical frame with no tilt or roll, in the base frame: z forward, x right, y down.
  Eigen::Matrix3d base_R_level;
  base_R_level.col(0) = Eigen::Vector3d(0, -1, 0);
  base_R_level.col(1) = Eigen::Vector3d(0, 0, -1);
  base_R_level.col(2) = Eigen::Vector3d(1, 0, 0);
  // Keep the nominal heading (yaw about the base z axis) and forward/lateral offset.
  const Eigen::Vector3d forward = nominal.linear().col(2);
  const double yaw = std::atan2(forward.y(), forward.x());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                 Eigen::AngleAxisd(fit.tilt_rad, Eigen::Vector3d::UnitY()).toRotationMatrix() * base_R_level *
                 Eigen::AngleAxisd(fit.roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out.translation() = Eigen::Vector3d(nominal.translation().x(), nominal.translation().y(), fit.camera_height_m);
  return out;
}

}  // namespace corridor::nav
