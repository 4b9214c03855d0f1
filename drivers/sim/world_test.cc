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

// A world as people download them: Gazebo's sun and ground plane (as model:// and as Gazebo Fuel URLs), lights, a mesh
// named file://meshes/... relative to the world's folder, a model's mesh by model://, cylinders. It loads from any
// working directory, with what the simulator does not draw left out.
TEST(LoadWorldTest, AWorldFromAPublicRepositoryOpens) {
  const fs::path dir = fs::temp_directory_path() / ("corridor_gz_" + std::to_string(::getpid()));
  fs::create_directories(dir / "worlds/meshes");
  fs::create_directories(dir / "models/crate/meshes");
  // A 1 x 0.2 x 1 m wall (OBJ, as assimp reads it), at the world's folder's meshes/; the crate model's own box.
  const auto box_obj = [](const fs::path& file, float sx, float sy, float sz) {
    std::ofstream obj(file);
    for (int i = 0; i < 8; ++i)
      obj << "v " << (i & 1 ? sx : 0) << ' ' << (i & 2 ? sy : 0) << ' ' << (i & 4 ? sz : 0) << '\n';
    obj << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  };
  box_obj(dir / "worlds/meshes/wall.obj", 1.0f, 0.2f, 1.0f);
  box_obj(dir / "models/crate/meshes/crate.obj", 0.4f, 0.4f, 0.4f);
  std::ofstream(dir / "models/crate/model.sdf")
      << "<sdf version='1.6'><model name='crate'><link name='l'><collision name='c'><geometry><mesh>"
         "<uri>model://crate/meshes/crate.obj</uri></mesh></geometry></collision></link></model></sdf>";
  std::ofstream(dir / "worlds/office.world")
      << "<?xml version='1.0'?><sdf version='1.6'><world name='default'>"
         "<include><uri>model://sun</uri></include>"
         "<include><uri>model://ground_plane</uri></include>"
         "<include><uri>https://fuel.gazebosim.org/1.0/OpenRobotics/models/Ground%20Plane</uri></include>"
         "<include><uri>https://fuel.gazebosim.org/1.0/OpenRobotics/models/Sun</uri></include>"
         "<light name='lamp' type='point'><pose>0 0 2 0 0 0</pose></light>"
         "<physics type='ode'/><scene><ambient>0.4 0.4 0.4 1</ambient></scene>"
         "<model name='walls'><static>true</static><pose>2 2 0 0 0 0</pose><link name='l'><collision name='c'>"
         "<geometry><mesh><uri>file://meshes/wall.obj</uri></mesh></geometry></collision></link></model>"
         "<model name='pillar'><pose>4 1 0.5 0 0 0</pose><link name='l'><collision name='c'><geometry>"
         "<cylinder><radius>0.2</radius><length>1</length></cylinder></geometry></collision></link></model>"
         "<include><uri>model://crate</uri><pose>0 0 0 0 0 0</pose></include>"
         "</world></sdf>";
  const fs::path cwd = fs::current_path();
  fs::current_path("/");  // not the world's folder: URIs must not depend on where the daemon runs
  World world;
  EXPECT_NO_THROW(world = LoadWorld(dir / "worlds/office.world", WorldOptions{}));
  fs::current_path(cwd);
  const auto occupied = [&](double x, double y) {
    const auto c = world.collision.WorldToCell({x, y});
    return c && world.collision.at(*c) == nav::kOccupiedCell;
  };
  EXPECT_TRUE(occupied(2.5, 2.1)) << "the wall from file://meshes/wall.obj";
  EXPECT_TRUE(occupied(4.0, 1.0)) << "the pillar";
  EXPECT_TRUE(occupied(0.2, 0.2)) << "the crate";
  EXPECT_FALSE(occupied(3.0, 1.0));
  // A model that is nowhere still stops the loader, naming what is missing and where it looked.
  std::ofstream(dir / "worlds/chair.world")
      << "<sdf version='1.6'><world name='w'>"
         "<include><uri>https://fuel.gazebosim.org/1.0/OpenRobotics/models/Office%20Chair</uri></include>"
         "</world></sdf>";
  try {
    LoadWorld(dir / "worlds/chair.world", WorldOptions{});
    ADD_FAILURE() << "a missing model loaded";
  } catch (const WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("'Office Chair'"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace corridor::drivers::sim
