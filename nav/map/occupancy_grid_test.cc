#include "nav/map/occupancy_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace corridor::nav {
namespace {

TEST(OccupancyGridTest, CellCenterMapsBackToItsCellUnderRotatedOrigins) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    const OccupancyGrid g(40, 30, 0.05, Pose2{u(rng), u(rng), u(rng)});
    for (int i = 0; i < 40; ++i) {
      const CellIndex c{i, (i * 7) % 30};
      EXPECT_EQ(g.WorldToCell(g.CellCenter(c)), c);
    }
  }
}

TEST(OccupancyGridTest, PointsFarOffTheMapOrNotNumbersHaveNoCell) {
  const OccupancyGrid g(40, 30, 0.05, Pose2{1.0, 2.0, 0.3});
  EXPECT_FALSE(g.WorldToCell({1.0, 5.9e27}));  // fuzz_bodies: a waypoint's y, far beyond int
  EXPECT_FALSE(g.WorldToCell({-1e300, 0.0}));
  EXPECT_FALSE(g.WorldToCell({std::nan(""), 2.0}));
  EXPECT_FALSE(g.WorldToCell({std::numeric_limits<double>::infinity(), 2.0}));
}

TEST(OccupancyGridTest, RejectsNonPositiveResolution) {
  EXPECT_THROW(OccupancyGrid(1, 1, 0.0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
