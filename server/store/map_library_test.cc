#include "server/store/map_library.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include <gtest/gtest.h>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

class MapLibraryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor_maps_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static nav::OccupancyGrid Grid(int width, std::int8_t value) {
    return nav::OccupancyGrid(width, 10, 0.05, nav::Pose2{}, value);
  }
  static bool Listed(const MapLibrary& maps, const std::string& name) {
    const auto names = maps.Names();
    return std::find(names.begin(), names.end(), name) != names.end();
  }
  fs::path dir_;
};

// Mapping saves a new map and makes it the one in use: the building's map, configured and never edited (so never saved
// in the state directory), must stay listed and selectable, with its own cells.
TEST_F(MapLibraryTest, TheMapItStartedWithStaysWhenANewMapIsMade) {
  MapLibrary maps(dir_, "building", Grid(20, nav::kFreeCell), nullptr);
  maps.Add("made", Grid(12, nav::kOccupiedCell));
  EXPECT_EQ(maps.active()->name, "made");
  EXPECT_TRUE(Listed(maps, "building"));
  EXPECT_TRUE(Listed(maps, "made"));
  EXPECT_TRUE(maps.Contains("building"));
  EXPECT_EQ(maps.Grid("building")->width(), 20);
  maps.Select("building");
  EXPECT_EQ(maps.active()->name, "building");
  EXPECT_EQ(maps.active()->grid.width(), 20);
  EXPECT_EQ(maps.active()->grid.at({3, 3}), nav::kFreeCell);
  // The new map is kept too, and no name is taken twice.
  EXPECT_TRUE(Listed(maps, "made"));
  EXPECT_THROW(maps.Add("building", Grid(5, nav::kFreeCell)), MapEditError);
  EXPECT_THROW(maps.Add("made", Grid(5, nav::kFreeCell)), MapEditError);
  EXPECT_THROW(maps.Select("nowhere"), MapEditError);
}

// An edit of the map it started with is saved and is what selecting it gives back.
TEST_F(MapLibraryTest, AnEditedInitialMapComesBackEdited) {
  MapLibrary maps(dir_, "building", Grid(20, nav::kFreeCell), nullptr);
  maps.EditCells({{2, 2, nav::kOccupiedCell}});
  maps.Add("made", Grid(12, nav::kFreeCell));
  maps.Select("building");
  EXPECT_EQ(maps.active()->grid.at({2, 2}), nav::kOccupiedCell);
  EXPECT_EQ(maps.active()->grid.at({3, 3}), nav::kFreeCell);
}

}  // namespace
}  // namespace corridor::server
