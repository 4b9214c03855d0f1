#include "nav/ground/voxel_obstacles.h"

#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

// Voxel indices packed into one key: 21 bits each, offset so that negative indices fit.
std::uint64_t Key(const Eigen::Vector3f& p, float inverse_leaf) {
  constexpr std::int64_t kOffset = 1 << 20;
  const auto index = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v * inverse_leaf)) + kOffset) & 0x1FFFFF;
  };
  return index(p.x()) | (index(p.y()) << 21) | (index(p.z()) << 42);
}

}  // namespace

VoxelObstacles::VoxelObstacles(const PinholeCamera& camera, const VoxelObstacleOptions& options)
    : camera_(camera), options_(options) {
  if (!camera.Valid()) throw std::invalid_argument("VoxelObstacles: the camera needs a positive size and focal length");
  if (options.voxel_m <= 0.0) throw std::invalid_argument("VoxelObstacles: voxel_m must be positive");
  rays_ = BaseFrameRays(camera);
  cloud_.reserve(rays_.size());
}

const std::vector<Eigen::Vector2f>& VoxelObstacles::Process(const cv::Mat& depth) {
  if (depth.type() != CV_16UC1 || depth.cols != camera_.width || depth.rows != camera_.height) {
    throw std::invalid_argument("VoxelObstacles: expected a CV_16UC1 depth image of the camera's size");
  }
  const Eigen::Vector3f origin = camera_.base_T_camera.translation().cast<float>();
  const float min_z = static_cast<float>(options_.min_range_m);
  const float max_z = static_cast<float>(options_.max_range_m);
  cloud_.clear();
  for (int v = 0; v < depth.rows; ++v) {
    const auto* row = depth.ptr<std::uint16_t>(v);
    const Eigen::Vector3f* ray = &rays_[static_cast<std::size_t>(v) * depth.cols];
    for (int u = 0; u < depth.cols; ++u) {
      const float d = static_cast<float>(row[u]) * 0.001f;
      if (d < min_z || d > max_z) continue;  // also holes (0)
      cloud_.push_back(origin + ray[u] * d);
    }
  }
  // Voxel grid: the centroid of each occupied voxel, as PCL's VoxelGrid filter.
  voxels_.clear();
  const float inverse_leaf = static_cast<float>(1.0 / options_.voxel_m);
  for (const Eigen::Vector3f& p : cloud_) {
    Voxel& voxel = voxels_[Key(p, inverse_leaf)];
    voxel.sum += p;
    ++voxel.count;
  }
  obstacles_.clear();
  for (const auto& [key, voxel] : voxels_) {
    if (voxel.count < options_.min_points) continue;
    const Eigen::Vector3f centroid = voxel.sum / static_cast<float>(voxel.count);
    if (centroid.z() >= options_.min_height_m && centroid.z() <= options_.max_height_m) {
      obstacles_.emplace_back(centroid.x(), centroid.y());
    }
  }
  return obstacles_;
}

}  // namespace corridor::nav
