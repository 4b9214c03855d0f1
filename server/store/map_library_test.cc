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

// A map exported as map_server files comes back as the same grid when imported under another name, not made active;
// files that are not a map are refused saying why, and nothing is left behind.
TEST_F(MapLibraryTest, AMapExportedAndImportedIsTheSameGridAndBadFilesAreRefused) {
  MapLibrary maps(dir_, "building", Grid(20, nav::kFreeCell), nullptr);
  nav::OccupancyGrid made(16, 9, 0.1, nav::Pose2{-1.5, 2.0, 0.0}, nav::kUnknownCell);
  made.at({1, 2}) = nav::kOccupiedCell;
  made.at({5, 5}) = nav::kFreeCell;
  maps.Add("made", made);
  maps.Select("building");
  const auto [yaml, png] = maps.Files("made");
  EXPECT_NE(yaml.find("image: made.png"), std::string::npos) << yaml;
  maps.Import("copy", yaml, png);
  EXPECT_EQ(maps.active()->name, "building") << "an import is not made active";
  ASSERT_TRUE(Listed(maps, "copy"));
  const auto copy = maps.Grid("copy");
  EXPECT_EQ(copy->width(), 16);
  EXPECT_EQ(copy->height(), 9);
  EXPECT_DOUBLE_EQ(copy->resolution_m(), 0.1);
  EXPECT_NEAR(copy->origin().x_m, -1.5, 1e-9);
  EXPECT_EQ(copy->cells(), made.cells());

  EXPECT_THROW(maps.Import("copy", yaml, png), MapEditError) << "taken";
  EXPECT_THROW(maps.Import("../up", yaml, png), MapEditError) << "not a name";
  EXPECT_THROW(maps.Import("bad-image", yaml, "not an image"), MapEditError);
  try {
    maps.Import("bad-yaml", "image: x.png\nresolution: -1\norigin: [0, 0, 0]\n", png);
    ADD_FAILURE() << "a negative resolution was taken";
  } catch (const MapEditError& e) {
    EXPECT_NE(std::string(e.what()).find("not a map_server map"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(Listed(maps, "bad-image"));
  EXPECT_FALSE(Listed(maps, "bad-yaml"));
  for (const auto& entry : fs::directory_iterator(dir_ / "maps")) {
    EXPECT_NE(entry.path().filename().string()[0], '.') << "left behind: " << entry.path();
  }
}

// Saved maps are renamed and deleted; the configured one and the one in use are not.
TEST_F(MapLibraryTest, SavedMapsAreRenamedAndDeletedButNotTheConfiguredOrTheActiveOne) {
  MapLibrary maps(dir_, "building", Grid(20, nav::kFreeCell), nullptr);
  maps.AddConfigured("floor2", dir_ / "nowhere.yaml");
  maps.Add("made", Grid(12, nav::kOccupiedCell));
  EXPECT_THROW(maps.Rename("made", "other"), MapEditError) << "in use";
  EXPECT_THROW(maps.Delete("made"), MapEditError) << "in use";
  maps.Select("building");
  EXPECT_THROW(maps.Rename("building", "other"), MapEditError) << "configured";
  EXPECT_THROW(maps.Delete("floor2"), MapEditError) << "configured";
  EXPECT_THROW(maps.Rename("made", "building"), MapEditError) << "taken";
  EXPECT_THROW(maps.Rename("made", "a/b"), MapEditError) << "not a name";
  EXPECT_THROW(maps.Delete("nowhere"), MapEditError) << "unknown";
  maps.Rename("made", "kitchen");
  EXPECT_FALSE(Listed(maps, "made"));
  ASSERT_TRUE(Listed(maps, "kitchen"));
  EXPECT_EQ(maps.Grid("kitchen")->width(), 12);
  maps.Delete("kitchen");
  EXPECT_FALSE(Listed(maps, "kitchen"));
  EXPECT_FALSE(maps.Contains("kitchen"));
}

}  // namespace
}  // namespace corridor::server
