#include "nav/localization/range_scan.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_set>

namespace corridor::nav {

RangeScan ScanFromRanges(const Pose2& base_T_sensor, double angle_min_rad, double increment_rad,
                         std::span<const float> ranges_m, const RangeLimits& limits, const BeamMotion& motion) {
  RangeScan scan;
  scan.origin = base_T_sensor.translation().cast<float>();
  scan.hits.reserve(ranges_m.size());
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    const double r = ranges_m[i];
    if (!(r >= limits.min_range_m)) {
      if (!std::isinf(r)) continue;  // NaN or too short: nothing known along this beam
    }
    const double angle = angle_min_rad + static_cast<double>(i) * increment_rad;
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    const Pose2 sensor = motion ? motion(i) * base_T_sensor : base_T_sensor;
    if (r >= limits.max_range_m) {
      scan.misses.push_back(sensor.Transform(direction * limits.miss_length_m).cast<float>());
    } else {
      scan.hits.push_back(sensor.Transform(direction * r).cast<float>());
    }
  }
  return scan;
}

std::vector<Eigen::Vector2f> VoxelFilter(std::span<const Eigen::Vector2f> points, double voxel_m) {
  if (!(voxel_m > 0.0)) throw std::invalid_argument("VoxelFilter: voxel size must be positive");
  std::unordered_set<std::uint64_t> taken;
  taken.reserve(points.size());
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points.size());
  for (const Eigen::Vector2f& p : points) {
    const auto ix = static_cast<std::int32_t>(std::floor(p.x() / voxel_m));
    const auto iy = static_cast<std::int32_t>(std::floor(p.y() / voxel_m));
    const std::uint64_t key =
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
    if (taken.insert(key).second) kept.push_back(p);
  }
  return kept;
}

std::vector<Eigen::Vector2f> TransformPoints(const Pose2& pose, std::span<const Eigen::Vector2f> points) {
  const float c = static_cast<float>(std::cos(pose.yaw_rad));
  const float s = static_cast<float>(std::sin(pose.yaw_rad));
  const Eigen::Vector2f t(static_cast<float>(pose.x_m), static_cast<float>(pose.y_m));
  std::vector<Eigen::Vector2f> out;
  out.reserve(points.size());
  for (const Eigen::Vector2f& p : points)
    out.emplace_back(c * p.x() - s * p.y() + t.x(), s * p.x() + c * p.y() + t.y());
  return out;
}

}  // namespace corridor::nav
