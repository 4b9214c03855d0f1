// The 3D map: an OctoMap occupancy octree (Hornung et al. 2013, liboctomap) built from depth frames at the robot's
// estimated poses. Each frame's pixels (subsampled) are rays from the camera: the voxels they cross become more
// likely free, the voxels they end in more likely occupied, with OctoMap's clamped log-odds, so a person who walked
// away or a chair moved is cleared by the next look. What stands between the step height and the robot's height
// (table tops a laser passes under, shelves, overhangs) is projected onto a 2D grid for the planner's costmap.
//
// Written to and read from OctoMap's binary format (.bt, what octovis and ROS's octomap_server read).
#pragma once

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"

namespace octomap {
class OcTree;
}

namespace corridor::nav {

struct OccupancyOctreeOptions {
  double resolution_m = 0.05;
  double max_range_m = 3.0;  // depth farther than this only clears space up to here (its noise grows as range²)
  double min_range_m = 0.2;
  int pixel_step = 2;     // every pixel_step-th pixel of every pixel_step-th row
  double prob_hit = 0.7;  // OctoMap's sensor model
  double prob_miss = 0.4;
  // ProjectOccupied counts a voxel only at least this likely occupied (OctoMap's own threshold is 0.5). At 0.9 a
  // voxel must have been seen occupied three times more than free: a person walking past is not, a table is.
  double project_min_probability = 0.5;
};

// A .bt that cannot be read; what() says why.
class OctreeFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An occupied leaf: its centre (map frame, z up from the floor) and its edge length.
struct OccupiedVoxel {
  Eigen::Vector3f center;
  float size_m = 0.0f;
};

class OccupancyOctree {
 public:
  // Throws std::invalid_argument for a non-positive resolution, step or range.
  explicit OccupancyOctree(const OccupancyOctreeOptions& options = {});
  // Reads a .bt (OctoMap binary) written by ToBinary or any OctoMap tool; its resolution replaces the option's.
  // Throws OctreeFormatError when the bytes are not one.
  static OccupancyOctree FromBinary(std::string_view bytes, const OccupancyOctreeOptions& options = {});
  OccupancyOctree(OccupancyOctree&&) noexcept;
  OccupancyOctree& operator=(OccupancyOctree&&) noexcept;
  ~OccupancyOctree();

  // One depth image (CV_16UC1 millimetres, 0 for no measurement, camera.width x camera.height) seen with the robot
  // at map_T_base. Throws std::invalid_argument for an image of another size or type.
  void InsertDepth(const cv::Mat& depth_mm, const PinholeCamera& camera, const Pose2& map_T_base);

  // Occupied voxels reaching between min_z_m and max_z_m, as cells of a grid with the geometry of `like`
  // (kOccupiedCell where one stands, kFreeCell elsewhere; the cells' values of `like` are not read).
  std::vector<std::int8_t> ProjectOccupied(const OccupancyGrid& like, double min_z_m, double max_z_m) const;
  // The same within `region` (map frame) only: `cells` (one per cell of `like`) is rewritten there and kept
  // elsewhere. What a few new frames changed costs their neighbourhood, not the whole octree.
  void ProjectOccupied(const OccupancyGrid& like, double min_z_m, double max_z_m, const Eigen::AlignedBox2d& region,
                       std::vector<std::int8_t>& cells) const;
  // Every occupied leaf, for drawing.
  std::vector<OccupiedVoxel> OccupiedVoxels() const;

  std::string ToBinary() const;
  double resolution_m() const;
  std::size_t leaf_count() const;
  std::size_t memory_bytes() const;

 private:
  OccupancyOctreeOptions options_;
  std::unique_ptr<octomap::OcTree> tree_;
  std::vector<Eigen::Vector3f> rays_;  // per sampled pixel, base frame, scaled to depth 1 (for the last camera)
  PinholeCamera rays_camera_;
};

}  // namespace corridor::nav
