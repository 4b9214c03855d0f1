// The comparison front end for MORP: what the point-cloud navigation pipelines do with a depth frame (Wang et al.'s
// point-cloud obstacle detection; the voxel-grid filters of PCL-based stacks). Every valid pixel becomes a point in
// the base frame; points are downsampled to one centroid per occupied voxel; voxels whose centroid stands between
// min_height_m and max_height_m above the floor are obstacles, returned as points on the floor plane.
//
// Kept deliberately plain and correct so that the scenario runner's speed ratio and outcome difference against MORP
// measure the method, not a weak implementation: contiguous buffers reused across frames, one hash map pass.
#pragma once

#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"

namespace corridor::nav {

struct VoxelObstacleOptions {
  double voxel_m = 0.05;       // the voxel grid's leaf size
  double min_height_m = 0.05;  // lower: floor (and noise on it)
  double max_height_m = 1.2;   // higher: passed under
  double min_range_m = 0.2;
  double max_range_m = 4.0;  // farther points are dropped before the grid
  int min_points = 2;        // voxels with fewer points are noise
};

class VoxelObstacles {
 public:
  // Throws std::invalid_argument for an unusable camera or a non-positive voxel size.
  VoxelObstacles(const PinholeCamera& camera, const VoxelObstacleOptions& options);

  // The obstacles in one depth image (CV_16UC1 millimetres, 0 for holes), as (x forward, y left) points in the base
  // frame, one per obstacle voxel. Thread-compatible; reuses its buffers.
  const std::vector<Eigen::Vector2f>& Process(const cv::Mat& depth);
  // The point cloud of the last Process, base frame.
  const std::vector<Eigen::Vector3f>& cloud() const { return cloud_; }

 private:
  struct Voxel {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    int count = 0;
  };

  PinholeCamera camera_;
  VoxelObstacleOptions options_;
  std::vector<Eigen::Vector3f> rays_;  // per pixel, base frame, scaled by depth 1
  std::vector<Eigen::Vector3f> cloud_;
  std::unordered_map<std::uint64_t, Voxel> voxels_;
  std::vector<Eigen::Vector2f> obstacles_;
};

}  // namespace corridor::nav
