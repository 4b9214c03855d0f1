#include "nav/map/log_odds_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace corridor::nav {
namespace {

TEST(LogOddsGridTest, RepeatedHitsFollowBayesAndClamp) {
  LogOddsGrid g(10, 10, 0.1, {});
  EXPECT_DOUBLE_EQ(g.Probability({3, 3}), 0.5);
  g.Update({3, 3}, true);
  EXPECT_NEAR(g.Probability({3, 3}), 0.7, 1e-6);
  g.Update({3, 3}, true);
  // Two independent hits: odds multiply, (7/3)^2 = 49/9, p = 49/58.
  EXPECT_NEAR(g.Probability({3, 3}), 49.0 / 58.0, 1e-6);
  for (int i = 0; i < 100; ++i) g.Update({3, 3}, true);
  EXPECT_NEAR(g.log_odds({3, 3}), 3.5, 1e-6);
  // Clamped, so a few misses bring it back down: the world may change (a door closes, a chair moves).
  for (int i = 0; i < 14; ++i) g.Update({3, 3}, false);
  EXPECT_LT(g.Probability({3, 3}), 0.5);
  g.Update({-1, 3}, true);  // outside: ignored
}

TEST(LogOddsGridTest, RaysClearTheirPathAndMarkTheirEnd) {
  LogOddsGrid g(100, 100, 0.05, Pose2{-2.5, -2.5, 0.0});
  // A wall at x = 1.0 seen from the origin by many beams, several times.
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (int k = -20; k <= 20; ++k) {
      const double a = k * std::numbers::pi / 120.0;
      g.IntegrateRay({0.0, 0.0}, {1.0, std::tan(a)}, true);
    }
    g.IntegrateRay({0.0, 0.0}, {-2.0, 0.0}, false);  // nothing there within range
  }
  const OccupancyGrid m = g.ToOccupancyGrid();
  EXPECT_EQ(m.at(*m.WorldToCell({1.01, 0.0})), kOccupiedCell);
  EXPECT_EQ(m.at(*m.WorldToCell({1.01, 0.2})), kOccupiedCell);
  EXPECT_EQ(m.at(*m.WorldToCell({0.5, 0.0})), kFreeCell);
  EXPECT_EQ(m.at(*m.WorldToCell({-1.9, 0.0})), kFreeCell);
  EXPECT_EQ(m.at(*m.WorldToCell({0.0, 2.0})), kUnknownCell);  // never seen
}

}  // namespace
}  // namespace corridor::nav
