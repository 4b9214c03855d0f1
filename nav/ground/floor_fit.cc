#include "nav/ground/floor_fit.h"

#include <cmath>
#include <numbers>

#include "nav/geometry/plane_fit.h"

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
  const auto floor_like = [&](Plane& plane) {
    if (plane.normal.dot(up) < 0.0) plane = {-plane.normal, -plane.offset};
    // Not a wall or a table edge, and the camera above it.
    return plane.normal.dot(up) >= cos_max && plane.offset > 0.0;
  };
  const auto best = RansacPlane(points, {options.iterations, options.inlier_threshold_m}, rng, floor_like);
  if (!best || best->second < options.min_inlier_fraction * static_cast<double>(points.size())) return std::nullopt;
  const std::optional<Plane> refined = RefinePlane(points, best->first, options.inlier_threshold_m);
  if (!refined) return std::nullopt;
  const Eigen::Vector3d& n = refined->normal;
  const int inliers = best->second;

  FloorFit fit;
  fit.normal = n;
  fit.offset = refined->offset;
  fit.camera_height_m = fit.offset;  // distance from the optical centre to the plane
  // The optical axis (0, 0, 1) makes angle asin(n . z) with the floor; pitched down, it points into the floor.
  fit.tilt_rad = -std::asin(std::clamp(n.z(), -1.0, 1.0));
  fit.roll_rad = std::atan2(n.x(), -n.y());
  fit.inliers = inliers;
  fit.inlier_fraction = static_cast<double>(inliers) / static_cast<double>(points.size());
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
