#include "nav/map/zones.h"

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

TEST(ZonesTest, ValidateNamesTheProblem) {
  Zone z{"z", "n", ZoneKind::kKeepOut, {{0, 0}, {1, 0}}, 0.0};
  EXPECT_THROW(Validate(z), InvalidZone);
  z.polygon = {{0, 0}, {1, 0}, {2, 0}};
  EXPECT_THROW(Validate(z), InvalidZone);  // no area
  z.polygon = {{0, 0}, {1, 0}, {1, 1}};
  EXPECT_NO_THROW(Validate(z));
  z.kind = ZoneKind::kSpeedLimit;
  EXPECT_THROW(Validate(z), InvalidZone);  // a speed zone needs its speed
  z.max_speed_mps = 0.3;
  EXPECT_NO_THROW(Validate(z));
  z.polygon[1] = {std::nan(""), 0};
  EXPECT_THROW(Validate(z), InvalidZone);
}

TEST(ZonesTest, ContainsUsesTheEvenOddRule) {
  const std::vector<Eigen::Vector2d> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_TRUE(Contains(square, {1, 1}));
  EXPECT_FALSE(Contains(square, {3, 1}));
  EXPECT_FALSE(Contains(square, {-0.1, 1}));
}

TEST(ZonesTest, RasterizeMarksCellsInsideAndThinZonesAreNotLost) {
  const OccupancyGrid g(100, 100, 0.1, Pose2{-5.0, -5.0, 0.0});
  std::vector<std::uint8_t> mask(g.cells().size(), 0);
  Rasterize({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, g, mask, 7);
  EXPECT_EQ(mask[g.WorldToCell({0.0, 0.0})->y * 100 + g.WorldToCell({0.0, 0.0})->x], 7);
  EXPECT_EQ(mask[g.WorldToCell({2.0, 0.0})->y * 100 + g.WorldToCell({2.0, 0.0})->x], 0);
  const int inside = static_cast<int>(std::count(mask.begin(), mask.end(), 7));
  EXPECT_NEAR(inside, 400, 84);  // 2 x 2 m at 10 cm, plus the outline cells
  // A zone 2 cm thin, narrower than a cell, still marks the cells it crosses.
  std::fill(mask.begin(), mask.end(), 0);
  Rasterize({{0.03, -2}, {0.05, -2}, {0.05, 2}, {0.03, 2}}, g, mask, 1);
  EXPECT_GE(std::count(mask.begin(), mask.end(), 1), 40);
}

}  // namespace
}  // namespace corridor::nav
