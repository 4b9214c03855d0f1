#include "drivers/sim/world.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "nav/map/map_io.h"

namespace corridor::drivers::sim {
namespace {

namespace fs = std::filesystem;

using testing::SourceDir;

TEST(WorldFromMapTest, CollisionGridIsTheMapsOccupiedCellsAndWallsAreExtruded) {
  const nav::OccupancyGrid map = nav::LoadMap(SourceDir() / "tests/data/maps/lse_arena/lse_arena.yaml");
  WorldOptions options;
  options.wall_height_m = 2.0;
  const World world = WorldFromMap(map, options);
  for (std::size_t i = 0; i < map.cells().size(); ++i) {
    EXPECT_EQ(world.collision.cells()[i] == nav::kOccupiedCell, map.cells()[i] == nav::kOccupiedCell);
  }
  const Eigen::AlignedBox3f b = world.mesh.Bounds();
  EXPECT_NEAR(b.max().z(), 2.0f, 1e-5f);
  EXPECT_NEAR(b.min().x(), 0.0f, 1e-5f);
  EXPECT_NEAR(b.max().x(), 4.0f, 1e-5f);  // 80 cells at 5 cm
}

TEST(LoadWorldTest, SmallHouseSdfMatchesItsOwnSlamMap) {
  WorldOptions options;
  const World world = LoadWorld(SourceDir() / "config/worlds/small_house/worlds/small_house.world", options);
  const Eigen::AlignedBox3f b = world.mesh.Bounds();
  // The house is about 20 x 13 m with a ceiling under 4 m: Z-up and metres were honoured.
  EXPECT_GT(b.sizes().x(), 15.0f);
  EXPECT_LT(b.sizes().x(), 25.0f);
  EXPECT_GT(b.sizes().y(), 8.0f);
  EXPECT_LT(b.sizes().y(), 16.0f);
  EXPECT_LT(b.max().z(), 4.0f);
  EXPECT_GT(b.max().z(), 2.0f);

  // Walls seen by the robot that mapped this world must stand where our collision slice has geometry.
  const nav::OccupancyGrid slam = nav::LoadMap(SourceDir() / "config/worlds/small_house/maps/map.yaml");
  const nav::OccupancyGrid& grid = world.collision;
  cv::Mat free_mask(grid.height(), grid.width(), CV_8UC1);
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      free_mask.at<std::uint8_t>(y, x) = grid.at({x, y}) == nav::kOccupiedCell ? 0 : 255;
    }
  }
  cv::Mat distance_cells;
  cv::distanceTransform(free_mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  int near = 0;
  int total = 0;
  for (int y = 0; y < slam.height(); ++y) {
    for (int x = 0; x < slam.width(); ++x) {
      if (slam.at({x, y}) != nav::kOccupiedCell) continue;
      ++total;
      const auto c = grid.WorldToCell(slam.CellCenter({x, y}));
      if (c && distance_cells.at<float>(c->y, c->x) * grid.resolution_m() <= 0.15) ++near;
    }
  }
  ASSERT_GT(total, 1000);
  EXPECT_GT(static_cast<double>(near) / total, 0.9) << near << " of " << total << " SLAM wall cells matched";
}

TEST(LoadWorldTest, BrokenWorldFilesGiveErrorsThatNameTheFile) {
  const fs::path dir = fs::temp_directory_path() / ("corridor_world_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto expect_error = [](const fs::path& file, const std::string& needle) {
    try {
      LoadWorld(file, WorldOptions{});
      ADD_FAILURE() << "expected an error for " << file;
    } catch (const WorldFileError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(dir / "absent.world", "does not exist");
  std::ofstream(dir / "bad.world") << "<sdf><world><include>";
  expect_error(dir / "bad.world", "not valid XML");
  std::ofstream(dir / "missing.world") << "<sdf><world><include><uri>model://nowhere</uri></include></world></sdf>";
  expect_error(dir / "missing.world", "model://nowhere");
  std::ofstream(dir / "junk.dae") << "this is no mesh";
  expect_error(dir / "junk.dae", "junk.dae");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace corridor::drivers::sim
