#include "nav/planner/distance_field.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <random>

#include "nav/map/map_io.h"

namespace corridor::nav {
namespace {

using testing::SourceDir;

struct Error {
  double max_cells = 0.0;
  double mean_cells = 0.0;
  double max_relative = 0.0;  // beyond two cells from obstacles
};

// Compares the fast-marching field with OpenCV's exact Euclidean distance transform on the same mask.
Error CompareWithExact(const std::vector<std::uint8_t>& obstacle, int width, int height) {
  const DistanceField fmm = FastMarchingDistance(obstacle, width, height, 1.0);
  cv::Mat free_mask(height, width, CV_8UC1);
  for (int i = 0; i < width * height; ++i) free_mask.data[i] = obstacle[i] ? 0 : 255;
  cv::Mat exact;
  cv::distanceTransform(free_mask, exact, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  Error e;
  int count = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double d = exact.at<float>(y, x);
      const double err = std::abs(fmm.at(x, y) - d);
      e.max_cells = std::max(e.max_cells, err);
      e.mean_cells += err;
      ++count;
      if (d > 2.0) e.max_relative = std::max(e.max_relative, err / d);
    }
  }
  e.mean_cells /= count;
  return e;
}

std::vector<std::uint8_t> ObstaclesOf(const OccupancyGrid& g) {
  std::vector<std::uint8_t> mask(g.cells().size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = g.cells()[i] != kFreeCell;
  return mask;
}

TEST(FastMarchingTest, StraightWallGivesExactDistances) {
  std::vector<std::uint8_t> mask(50 * 40, 0);
  for (int y = 0; y < 40; ++y) mask[y * 50] = 1;  // the wall x = 0
  const DistanceField f = FastMarchingDistance(mask, 50, 40, 0.05);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 50; ++x) EXPECT_NEAR(f.at(x, y), x * 0.05, 1e-5);
  }
}

TEST(FastMarchingTest, SinglePointSourceIsCloseToEuclidean) {
  const int n = 101;
  std::vector<std::uint8_t> mask(n * n, 0);
  mask[50 * n + 50] = 1;
  const Error e = CompareWithExact(mask, n, n);
  // A point source is the hardest case for an Eikonal solver on a grid (the front is most curved there).
  EXPECT_LT(e.max_relative, 0.02);
  EXPECT_LT(e.mean_cells, 0.15);
}

TEST(FastMarchingTest, RandomObstaclesAgreeWithOpenCvExactTransform) {
  std::mt19937 rng(17);
  std::bernoulli_distribution occupied(0.01);
  const int w = 200;
  const int h = 150;
  std::vector<std::uint8_t> mask(w * h);
  for (auto& m : mask) m = occupied(rng);
  const Error e = CompareWithExact(mask, w, h);
  EXPECT_LT(e.max_cells, 0.3);
  EXPECT_LT(e.mean_cells, 0.05);
}

TEST(FastMarchingTest, RealMapsAgreeWithOpenCvExactTransform) {
  for (const char* map : {"tests/data/maps/lse_arena/lse_arena.yaml", "tests/data/maps/avz/avz.yaml",
                          "tests/data/maps/depot/depot.yaml", "config/worlds/willow_garage/willow-full-0.05.yaml"}) {
    SCOPED_TRACE(map);
    const OccupancyGrid g = LoadMap(SourceDir() / map);
    const Error e = CompareWithExact(ObstaclesOf(g), g.width(), g.height());
    // Measured: at most 0.25 cells and 0.04 cells on average on these maps.
    EXPECT_LT(e.max_cells, 0.3);
    EXPECT_LT(e.mean_cells, 0.05);
  }
}

TEST(FastMarchingTest, MarchStopsAtTheLimit) {
  std::vector<std::uint8_t> mask(100, 0);
  mask[0] = 1;
  const DistanceField f = FastMarchingDistance(mask, 100, 1, 0.1, {.max_distance_m = 2.0});
  EXPECT_NEAR(f.at(20, 0), 2.0, 1e-5);
  EXPECT_TRUE(std::isinf(f.at(30, 0)));
}

}  // namespace
}  // namespace corridor::nav
