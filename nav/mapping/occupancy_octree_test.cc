#include "nav/mapping/occupancy_octree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

// A 320 x 240 camera 0.3 m above the floor looking straight ahead (optical z = base x).
PinholeCamera ForwardCamera() {
  PinholeCamera camera;
  camera.width = 320;
  camera.height = 240;
  camera.fx = camera.fy = 277.0;  // about 60 x 47 degrees
  camera.cx = 159.5;
  camera.cy = 119.5;
  Eigen::Matrix3d optical_to_base;
  optical_to_base << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  camera.base_T_camera.linear() = optical_to_base;
  camera.base_T_camera.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
  return camera;
}

// The depth image of a constructed room seen from the origin looking along +x: the floor, a wall at x = 2.8 m and,
// with `table`, a table top 0.70-0.75 m high over x in [1.5, 2.5] and y in [-0.5, 0.5] (no legs: a laser at 0.2 m
// would see nothing of it).
cv::Mat RoomDepth(const PinholeCamera& camera, bool table) {
  cv::Mat depth(camera.height, camera.width, CV_16UC1, cv::Scalar(0));
  const Eigen::Vector3d o = camera.base_T_camera.translation();
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d d = camera.base_T_camera.linear() * camera.Ray(u, v);  // depth 1 along the optical axis
      double t = (2.8 - o.x()) / d.x();
      if (d.z() < 0.0) t = std::min(t, -o.z() / d.z());
      if (table && d.z() > 0.0) {
        const double hit = (0.70 - o.z()) / d.z();
        const Eigen::Vector3d p = o + hit * d;
        if (p.x() >= 1.5 && p.x() <= 2.5 && std::abs(p.y()) <= 0.5) t = std::min(t, hit);
      }
      depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(t * 1000.0));
    }
  }
  return depth;
}

OccupancyGrid Grid() { return OccupancyGrid(80, 40, 0.05, Pose2{-0.5, -1.0, 0.0}); }

// The share of occupied cells among those whose centres lie in [x0, x1] x [y0, y1].
double OccupiedShare(const OccupancyGrid& grid, const std::vector<std::int8_t>& cells, double x0, double x1, double y0,
                     double y1) {
  int occupied = 0, total = 0;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d c = grid.CellCenter({x, y});
      if (c.x() < x0 || c.x() > x1 || c.y() < y0 || c.y() > y1) continue;
      ++total;
      occupied += cells[static_cast<std::size_t>(y) * grid.width() + x] == kOccupiedCell;
    }
  }
  return total == 0 ? 0.0 : static_cast<double>(occupied) / total;
}

TEST(OccupancyOctree, ProjectsATableTopButNotTheFloor) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  const cv::Mat depth = RoomDepth(camera, true);
  for (int i = 0; i < 3; ++i) octree.InsertDepth(depth, camera, Pose2{});
  const OccupancyGrid grid = Grid();
  const auto cells = octree.ProjectOccupied(grid, 0.1, 1.2);
  // The underside seen from below. The rays of every other row graze it 5 cm apart at x = 1.6 m, 12 cm at 2.5 m,
  // so some rows of cells are missed.
  EXPECT_GT(OccupiedShare(grid, cells, 1.55, 1.8, -0.3, 0.3), 0.75);
  EXPECT_GT(OccupiedShare(grid, cells, 1.55, 2.45, -0.3, 0.3), 0.6);
  EXPECT_EQ(OccupiedShare(grid, cells, 0.3, 1.4, -0.3, 0.3), 0.0);  // the floor before it is below the step height
  // The wall's face at x = 2.8 m (within max_range, 3 m) lies in the cell row either side of it.
  EXPECT_GT(OccupiedShare(grid, cells, 2.75, 2.85, -0.1, 0.1), 0.4);
  // A band that ends below the table sees none of it.
  EXPECT_EQ(OccupiedShare(grid, octree.ProjectOccupied(grid, 0.1, 0.6), 1.55, 2.45, -0.3, 0.3), 0.0);
}

TEST(OccupancyOctree, ProjectsARegionAndKeepsTheRestOfTheLayer) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  const OccupancyGrid grid = Grid();
  const auto whole = octree.ProjectOccupied(grid, 0.1, 1.2);
  // A layer of something else, rewritten over the table's half only.
  std::vector<std::int8_t> layer(whole.size(), kUnknownCell);
  const Eigen::AlignedBox2d region(Eigen::Vector2d(1.0, -1.0), Eigen::Vector2d(2.0, 1.0));
  octree.ProjectOccupied(grid, 0.1, 1.2, region, layer);
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * grid.width() + x;
      const Eigen::Vector2d c = grid.CellCenter({x, y});
      if (region.contains(c)) {
        EXPECT_EQ(layer[i], whole[i]) << x << ", " << y;
      } else {
        EXPECT_EQ(layer[i], kUnknownCell) << x << ", " << y;
      }
    }
  }
  std::vector<std::int8_t> wrong_size(10);
  EXPECT_THROW(octree.ProjectOccupied(grid, 0.1, 1.2, region, wrong_size), std::invalid_argument);
}

TEST(OccupancyOctree, ProjectsOnlyWhatWasSeenOftenEnoughWhenAsked) {
  // Seen once (a person walking past), a voxel is occupied but not likely enough for a layer asking 0.9.
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree(OccupancyOctreeOptions{.project_min_probability = 0.9});
  const OccupancyGrid grid = Grid();
  octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  EXPECT_EQ(OccupiedShare(grid, octree.ProjectOccupied(grid, 0.1, 1.2), 1.55, 1.8, -0.3, 0.3), 0.0);
  for (int i = 0; i < 2; ++i) octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  EXPECT_GT(OccupiedShare(grid, octree.ProjectOccupied(grid, 0.1, 1.2), 1.55, 1.8, -0.3, 0.3), 0.75);
}

TEST(OccupancyOctree, ClearsWhatIsGone) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  for (int i = 0; i < 3; ++i) octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  // The table carried away: the rays now pass where it stood and end on the wall behind.
  for (int i = 0; i < 10; ++i) octree.InsertDepth(RoomDepth(camera, false), camera, Pose2{});
  const OccupancyGrid grid = Grid();
  EXPECT_LT(OccupiedShare(grid, octree.ProjectOccupied(grid, 0.1, 1.2), 1.55, 2.45, -0.3, 0.3), 0.05);
}

TEST(OccupancyOctree, TurnsWithTheRobot) {
  // The robot at (1, 1) facing +y sees the table along +y: the table stands at y in [2.5, 3.5].
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{1.0, 1.0, std::numbers::pi / 2});
  const OccupancyGrid grid(60, 100, 0.05, Pose2{-0.5, -0.5, 0.0});
  const auto cells = octree.ProjectOccupied(grid, 0.1, 1.2);
  EXPECT_GT(OccupiedShare(grid, cells, 0.7, 1.3, 2.55, 2.8), 0.75);
  EXPECT_EQ(OccupiedShare(grid, cells, 0.7, 1.3, 1.3, 2.4), 0.0);
}

TEST(OccupancyOctree, RoundTripsThroughBinary) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  for (int i = 0; i < 3; ++i) octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  const std::string bytes = octree.ToBinary();
  const OccupancyOctree read = OccupancyOctree::FromBinary(bytes);
  EXPECT_DOUBLE_EQ(read.resolution_m(), 0.05);
  const OccupancyGrid grid = Grid();
  EXPECT_EQ(read.ProjectOccupied(grid, 0.1, 1.2), octree.ProjectOccupied(grid, 0.1, 1.2));
  EXPECT_EQ(read.OccupiedVoxels().size(), octree.OccupiedVoxels().size());
}

TEST(OccupancyOctree, RejectsBrokenFiles) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  octree.InsertDepth(RoomDepth(camera, true), camera, Pose2{});
  const std::string bytes = octree.ToBinary();
  const std::size_t data = bytes.find("\ndata\n") + 6;
  ASSERT_NE(data, std::string::npos + 6);
  EXPECT_THROW(OccupancyOctree::FromBinary("P5\n10 10\n255\n"), OctreeFormatError);
  EXPECT_THROW(OccupancyOctree::FromBinary(""), OctreeFormatError);
  EXPECT_THROW(OccupancyOctree::FromBinary(bytes.substr(0, data - 3)), OctreeFormatError);          // no "data" line
  EXPECT_THROW(OccupancyOctree::FromBinary(bytes.substr(0, bytes.size() - 1)), OctreeFormatError);  // truncated
  EXPECT_THROW(OccupancyOctree::FromBinary(bytes + "xx"), OctreeFormatError);                       // trailing bytes
  // Every node claiming eight inner children: OctoMap itself would recurse until the stack ran out.
  EXPECT_THROW(OccupancyOctree::FromBinary(bytes.substr(0, data) + std::string(4096, '\xff')), OctreeFormatError);
  std::string other_id = bytes;
  other_id.replace(other_id.find("id OcTree"), 9, "id ColorX");
  EXPECT_THROW(OccupancyOctree::FromBinary(other_id), OctreeFormatError);
}

TEST(OccupancyOctree, RejectsAnImageOfAnotherSize) {
  const PinholeCamera camera = ForwardCamera();
  OccupancyOctree octree;
  EXPECT_THROW(octree.InsertDepth(cv::Mat(10, 10, CV_16UC1, cv::Scalar(1000)), camera, Pose2{}), std::invalid_argument);
  EXPECT_THROW(octree.InsertDepth(cv::Mat(240, 320, CV_32FC1, cv::Scalar(1.0)), camera, Pose2{}),
               std::invalid_argument);
  EXPECT_THROW(OccupancyOctree(OccupancyOctreeOptions{.resolution_m = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
