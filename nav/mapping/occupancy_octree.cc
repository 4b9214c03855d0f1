#include "nav/mapping/occupancy_octree.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <octomap/OcTree.h>

namespace corridor::nav {
namespace {

constexpr std::string_view kBinaryHeader = "# Octomap OcTree binary file";
constexpr int kTreeDepth = 16;  // OctoMap's fixed depth

// OctoMap's reader trusts its input: a node whose bits claim children it does not have is read past the end of the
// stream, and nothing bounds the depth. So the bytes are walked here first, without building anything: each node is
// two bytes of two bits per child (01 occupied leaf, 10 free leaf, 11 inner node, 00 unknown), depth first, and
// the stream must end exactly after the root's last descendant, no deeper than the tree's depth.
void CheckTreeData(std::string_view data) {
  struct Pending {
    int depth;
  };
  std::vector<Pending> stack = {{0}};
  std::size_t at = 0;
  while (!stack.empty()) {
    const int depth = stack.back().depth;
    stack.pop_back();
    if (at + 2 > data.size()) throw OctreeFormatError("the octree's data ends inside a node");
    const auto bits = static_cast<unsigned>(static_cast<unsigned char>(data[at])) |
                      (static_cast<unsigned>(static_cast<unsigned char>(data[at + 1])) << 8);
    at += 2;
    int inner = 0;
    for (int child = 0; child < 8; ++child) {
      if (((bits >> (2 * child)) & 3u) == 3u) ++inner;
    }
    if (inner > 0 && depth + 1 >= kTreeDepth) throw OctreeFormatError("the octree is deeper than 16 levels");
    for (int i = 0; i < inner; ++i) stack.push_back({depth + 1});
  }
  if (at != data.size()) throw OctreeFormatError("bytes follow the octree's last node");
}

// The header of a .bt: its first line, then "key value" lines up to "data"; returns the data and the resolution.
std::string_view ParseHeader(std::string_view bytes, double& resolution_m) {
  std::size_t at = 0;
  const auto line = [&]() -> std::string_view {
    const std::size_t end = bytes.find('\n', at);
    if (end == std::string_view::npos) throw OctreeFormatError("the header ends before its 'data' line");
    const std::string_view text = bytes.substr(at, end - at);
    at = end + 1;
    return text;
  };
  if (line().substr(0, kBinaryHeader.size()) != kBinaryHeader) {
    throw OctreeFormatError("not an OctoMap binary file (.bt): its first line is not '" + std::string(kBinaryHeader) +
                            "'");
  }
  resolution_m = 0.0;
  std::string id;
  for (;;) {
    const std::string_view text = line();
    if (text.empty() || text.front() == '#') continue;
    if (text == "data") break;
    std::istringstream fields{std::string(text)};
    std::string key;
    fields >> key;
    if (key == "id") fields >> id;
    if (key == "res") fields >> resolution_m;
  }
  if (id != "OcTree") throw OctreeFormatError("the octree's id is '" + id + "', not 'OcTree'");
  if (!(resolution_m > 1e-4 && resolution_m < 100.0)) throw OctreeFormatError("the octree's resolution is not valid");
  return bytes.substr(at);
}

}  // namespace

OccupancyOctree::OccupancyOctree(const OccupancyOctreeOptions& options) : options_(options) {
  if (!(options.resolution_m > 0.0) || options.pixel_step < 1 || !(options.max_range_m > options.min_range_m)) {
    throw std::invalid_argument("octree: resolution, pixel step and range must be positive");
  }
  tree_ = std::make_unique<octomap::OcTree>(options.resolution_m);
  tree_->setProbHit(options.prob_hit);
  tree_->setProbMiss(options.prob_miss);
}

OccupancyOctree OccupancyOctree::FromBinary(std::string_view bytes, const OccupancyOctreeOptions& options) {
  double resolution_m = 0.0;
  CheckTreeData(ParseHeader(bytes, resolution_m));
  OccupancyOctreeOptions read = options;
  read.resolution_m = resolution_m;
  OccupancyOctree octree(read);
  std::istringstream in{std::string(bytes)};
  if (!octree.tree_->readBinary(in)) throw OctreeFormatError("OctoMap could not read the octree");
  return octree;
}

OccupancyOctree::OccupancyOctree(OccupancyOctree&&) noexcept = default;
OccupancyOctree& OccupancyOctree::operator=(OccupancyOctree&&) noexcept = default;
OccupancyOctree::~OccupancyOctree() = default;

void OccupancyOctree::InsertDepth(const cv::Mat& depth_mm, const PinholeCamera& camera, const Pose2& map_T_base) {
  if (depth_mm.type() != CV_16UC1 || depth_mm.cols != camera.width || depth_mm.rows != camera.height) {
    throw std::invalid_argument("octree: the depth image is not CV_16UC1 of the camera's size");
  }
  const int step = options_.pixel_step;
  if (rays_.empty() || rays_camera_.width != camera.width || rays_camera_.height != camera.height ||
      rays_camera_.fx != camera.fx || rays_camera_.fy != camera.fy || rays_camera_.cx != camera.cx ||
      rays_camera_.cy != camera.cy || !rays_camera_.base_T_camera.isApprox(camera.base_T_camera)) {
    rays_.clear();
    const Eigen::Matrix3d rotation = camera.base_T_camera.linear();
    for (int v = 0; v < camera.height; v += step) {
      for (int u = 0; u < camera.width; u += step) rays_.push_back((rotation * camera.Ray(u, v)).cast<float>());
    }
    rays_camera_ = camera;
  }
  // base -> map: a turn about z by the yaw, then the robot's position on the floor.
  const float c = static_cast<float>(std::cos(map_T_base.yaw_rad));
  const float s = static_cast<float>(std::sin(map_T_base.yaw_rad));
  const Eigen::Vector3f origin_base = camera.base_T_camera.translation().cast<float>();
  const auto to_map = [&](const Eigen::Vector3f& p) {
    return octomap::point3d(static_cast<float>(map_T_base.x_m) + c * p.x() - s * p.y(),
                            static_cast<float>(map_T_base.y_m) + s * p.x() + c * p.y(), p.z());
  };
  octomap::Pointcloud cloud;
  cloud.reserve(rays_.size());
  const float min_range = static_cast<float>(options_.min_range_m);
  std::size_t ray = 0;
  for (int v = 0; v < camera.height; v += step) {
    const auto* row = depth_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < camera.width; u += step, ++ray) {
      if (row[u] == 0) continue;  // no measurement: says nothing, not even free
      const float depth_m = static_cast<float>(row[u]) * 0.001f;
      if (depth_m < min_range) continue;
      cloud.push_back(to_map(origin_base + depth_m * rays_[ray]));
    }
  }
  // discretize: one ray per end voxel (several pixels end in most voxels near the camera).
  tree_->insertPointCloud(cloud, to_map(origin_base), options_.max_range_m, /*lazy_eval=*/false, /*discretize=*/true);
}

std::vector<std::int8_t> OccupancyOctree::ProjectOccupied(const OccupancyGrid& like, double min_z_m,
                                                          double max_z_m) const {
  std::vector<std::int8_t> cells(static_cast<std::size_t>(like.width()) * like.height(), kFreeCell);
  const Eigen::Vector2d lo = like.origin().translation();
  const Eigen::Vector2d hi = lo + Eigen::Vector2d(like.width(), like.height()) * like.resolution_m();
  ProjectOccupied(like, min_z_m, max_z_m, Eigen::AlignedBox2d(lo, hi), cells);
  return cells;
}

void OccupancyOctree::ProjectOccupied(const OccupancyGrid& like, double min_z_m, double max_z_m,
                                      const Eigen::AlignedBox2d& region, std::vector<std::int8_t>& cells) const {
  if (cells.size() != static_cast<std::size_t>(like.width()) * like.height()) {
    throw std::invalid_argument("octree: the layer has not one value per cell of the grid");
  }
  // The region in whole cells, clipped to the grid (its origin's yaw is 0 for every map the daemon loads:
  // map_server ignores it).
  const double r = like.resolution_m();
  const Eigen::Vector2d lo = like.origin().translation();
  const int cx0 = std::max(0, static_cast<int>(std::floor((region.min().x() - lo.x()) / r)));
  const int cy0 = std::max(0, static_cast<int>(std::floor((region.min().y() - lo.y()) / r)));
  const int cx1 = std::min(like.width(), static_cast<int>(std::ceil((region.max().x() - lo.x()) / r)));
  const int cy1 = std::min(like.height(), static_cast<int>(std::ceil((region.max().y() - lo.y()) / r)));
  if (cx0 >= cx1 || cy0 >= cy1) return;
  for (int y = cy0; y < cy1; ++y) {
    std::fill_n(cells.begin() + static_cast<std::ptrdiff_t>(y) * like.width() + cx0, cx1 - cx0, kFreeCell);
  }
  if (tree_->size() == 0) return;
  const octomap::point3d box_min(static_cast<float>(lo.x() + cx0 * r), static_cast<float>(lo.y() + cy0 * r),
                                 static_cast<float>(min_z_m));
  const octomap::point3d box_max(static_cast<float>(lo.x() + cx1 * r), static_cast<float>(lo.y() + cy1 * r),
                                 static_cast<float>(max_z_m));
  for (auto it = tree_->begin_leafs_bbx(box_min, box_max), end = tree_->end_leafs_bbx(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it) || it->getOccupancy() < options_.project_min_probability) continue;
    const double half = it.getSize() / 2.0;
    const double z = it.getZ();
    if (z + half <= min_z_m || z - half >= max_z_m) continue;
    // Every cell under the leaf (one, unless the leaf was pruned into a larger block), within the region.
    const int x0 = static_cast<int>(std::floor((it.getX() - half - lo.x()) / r + 1e-6));
    const int x1 = static_cast<int>(std::ceil((it.getX() + half - lo.x()) / r - 1e-6));
    const int y0 = static_cast<int>(std::floor((it.getY() - half - lo.y()) / r + 1e-6));
    const int y1 = static_cast<int>(std::ceil((it.getY() + half - lo.y()) / r - 1e-6));
    for (int y = std::max(cy0, y0); y < std::min(cy1, y1); ++y) {
      for (int x = std::max(cx0, x0); x < std::min(cx1, x1); ++x) {
        cells[static_cast<std::size_t>(y) * like.width() + x] = kOccupiedCell;
      }
    }
  }
}

std::vector<OccupiedVoxel> OccupancyOctree::OccupiedVoxels() const {
  std::vector<OccupiedVoxel> voxels;
  if (tree_->size() == 0) return voxels;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    voxels.push_back(
        {Eigen::Vector3f(static_cast<float>(it.getX()), static_cast<float>(it.getY()), static_cast<float>(it.getZ())),
         static_cast<float>(it.getSize())});
  }
  return voxels;
}

std::string OccupancyOctree::ToBinary() const {
  std::ostringstream out;
  tree_->writeBinaryConst(out);  // occupied or free per leaf; the tree itself keeps its probabilities
  return std::move(out).str();
}

double OccupancyOctree::resolution_m() const { return tree_->getResolution(); }
std::size_t OccupancyOctree::leaf_count() const { return tree_->getNumLeafNodes(); }
std::size_t OccupancyOctree::memory_bytes() const { return tree_->memoryUsage(); }

}  // namespace corridor::nav
