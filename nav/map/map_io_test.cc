#include "nav/map/map_io.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace corridor::nav {
namespace {

namespace fs = std::filesystem;

using testing::SourceDir;

class MapIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor_map_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path WriteYaml(const std::string& body, const std::string& name = "map.yaml") {
    std::ofstream(dir_ / name) << body;
    return dir_ / name;
  }

  fs::path dir_;
};

int CountCells(const OccupancyGrid& g, std::int8_t value) {
  return static_cast<int>(std::count(g.cells().begin(), g.cells().end(), value));
}

TEST_F(MapIoTest, LoadsRealGimpPgmWithHeaderComment) {
  const OccupancyGrid g = LoadMap(SourceDir() / "tests/data/maps/lse_arena/lse_arena.yaml");
  EXPECT_EQ(g.width(), 80);
  EXPECT_EQ(g.height(), 60);
  EXPECT_DOUBLE_EQ(g.resolution_m(), 0.05);
  // The arena is walled: the border rows are occupied and the middle is free.
  EXPECT_GT(CountCells(g, kOccupiedCell), 200);
  EXPECT_GT(CountCells(g, kFreeCell), 2000);
  EXPECT_EQ(g.at({40, 30}), kFreeCell);
}

TEST_F(MapIoTest, LoadsRealTrinaryMapWithUnknownSpace) {
  const OccupancyGrid g = LoadMap(SourceDir() / "tests/data/maps/avz/avz.yaml");
  EXPECT_EQ(g.width(), 975);
  EXPECT_EQ(g.height(), 477);
  // The image holds 303940 grey (205), 150467 white and 10668 black pixels.
  EXPECT_EQ(CountCells(g, kUnknownCell), 303940);
  EXPECT_EQ(CountCells(g, kFreeCell), 150467);
  EXPECT_EQ(CountCells(g, kOccupiedCell), 10668);
}

TEST_F(MapIoTest, GreyPixelsBelowFreeThresholdAreFreeAsInMapServer) {
  // depot.yaml sets free_thresh 0.25, so its grey 205 pixels (occupancy 0.196) are free, as nav2 loads them.
  const OccupancyGrid g = LoadMap(SourceDir() / "tests/data/maps/depot/depot.yaml");
  EXPECT_EQ(g.width(), 604);
  EXPECT_EQ(g.height(), 307);
  EXPECT_EQ(CountCells(g, kUnknownCell), 0);
  EXPECT_EQ(CountCells(g, kFreeCell), 170587 + 8894);
  EXPECT_EQ(CountCells(g, kOccupiedCell), 5947);
}

TEST_F(MapIoTest, ImageRowZeroIsTheTopOfTheMap) {
  cv::Mat image(2, 3, CV_8UC1, cv::Scalar(254));
  image.at<std::uint8_t>(0, 2) = 0;  // top-right pixel occupied
  cv::imwrite((dir_ / "m.pgm").string(), image);
  const OccupancyGrid g =
      LoadMap(WriteYaml("image: m.pgm\nresolution: 0.1\norigin: [1, 2, 0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"));
  EXPECT_EQ(g.at({2, 1}), kOccupiedCell);
  EXPECT_EQ(g.at({2, 0}), kFreeCell);
  // Integer origin values are accepted; the cell centre is in the map frame.
  EXPECT_TRUE(g.CellCenter({0, 0}).isApprox(Eigen::Vector2d(1.05, 2.05)));
  EXPECT_EQ(g.WorldToCell({1.25, 2.15}), (CellIndex{2, 1}));
  EXPECT_EQ(g.WorldToCell({0.99, 2.15}), std::nullopt);
}

TEST_F(MapIoTest, RgbaPngInScaleModeTreatsTransparentPixelsAsUnknown) {
  cv::Mat image(1, 4, CV_8UC4);
  image.at<cv::Vec4b>(0, 0) = {0, 0, 0, 255};        // black, opaque: occupied
  image.at<cv::Vec4b>(0, 1) = {255, 255, 255, 255};  // white, opaque: free
  image.at<cv::Vec4b>(0, 2) = {255, 255, 255, 0};    // transparent: unknown
  image.at<cv::Vec4b>(0, 3) = {150, 150, 150, 255};  // grey: scaled in between
  cv::imwrite((dir_ / "m.png").string(), image);
  const OccupancyGrid g =
      LoadMap(WriteYaml("image: m.png\nmode: scale\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"));
  EXPECT_EQ(g.at({0, 0}), kOccupiedCell);
  EXPECT_EQ(g.at({1, 0}), kFreeCell);
  EXPECT_EQ(g.at({2, 0}), kUnknownCell);
  EXPECT_GT(g.at({3, 0}), 0);
  EXPECT_LT(g.at({3, 0}), 100);
}

TEST_F(MapIoTest, NegateSwapsBlackAndWhite) {
  cv::Mat image(1, 2, CV_8UC1);
  image.at<std::uint8_t>(0, 0) = 0;
  image.at<std::uint8_t>(0, 1) = 255;
  cv::imwrite((dir_ / "m.pgm").string(), image);
  const OccupancyGrid g = LoadMap(WriteYaml("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 1\n"));
  EXPECT_EQ(g.at({0, 0}), kFreeCell);
  EXPECT_EQ(g.at({1, 0}), kOccupiedCell);
}

TEST_F(MapIoTest, RawModeKeepsPixelValuesUpTo100) {
  cv::Mat image(1, 3, CV_8UC1);
  image.at<std::uint8_t>(0, 0) = 0;
  image.at<std::uint8_t>(0, 1) = 42;
  image.at<std::uint8_t>(0, 2) = 200;
  cv::imwrite((dir_ / "m.png").string(), image);
  const OccupancyGrid g =
      LoadMap(WriteYaml("image: m.png\nmode: raw\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: false\n"));
  EXPECT_EQ(g.at({0, 0}), 0);
  EXPECT_EQ(g.at({1, 0}), 42);
  EXPECT_EQ(g.at({2, 0}), kUnknownCell);
}

TEST_F(MapIoTest, SaveThenLoadRoundTripsEveryCell) {
  const OccupancyGrid original = LoadMap(SourceDir() / "tests/data/maps/avz/avz.yaml");
  SaveMap(original, dir_ / "saved.yaml");
  const OccupancyGrid loaded = LoadMap(dir_ / "saved.yaml");
  ASSERT_EQ(loaded.width(), original.width());
  EXPECT_EQ(loaded.cells(), original.cells());
  EXPECT_FALSE(fs::exists(dir_ / "saved.yaml.tmp"));
}

TEST_F(MapIoTest, BrokenFilesGiveErrorsThatNameTheProblem) {
  auto expect_error = [&](const fs::path& yaml, const std::string& needle) {
    try {
      LoadMap(yaml);
      ADD_FAILURE() << "expected an error mentioning '" << needle << "'";
    } catch (const MapFileError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(dir_ / "absent.yaml", "cannot be opened");
  expect_error(WriteYaml("image: [unclosed\n", "a.yaml"), "not valid YAML");
  expect_error(WriteYaml("resolution: 0.05\norigin: [0, 0, 0]\n", "b.yaml"), "missing key 'image'");
  expect_error(WriteYaml("image: nope.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n", "c.yaml"), "does not exist");
  expect_error(WriteYaml("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n", "d.yaml"), "'resolution'");
  expect_error(WriteYaml("image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n", "e.yaml"), "'origin'");
  expect_error(WriteYaml("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n", "f.yaml"), "'mode'");
  expect_error(WriteYaml("image: m.pgm\nresolution: 0.05\norigin: [0,0,0]\nfree_thresh: 0.9\n", "g.yaml"),
               "thresholds");
  std::ofstream(dir_ / "torn.pgm") << "P5\n100 100\n255\nshort";
  expect_error(WriteYaml("image: torn.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n", "h.yaml"), "torn.pgm");
}

}  // namespace
}  // namespace corridor::nav
