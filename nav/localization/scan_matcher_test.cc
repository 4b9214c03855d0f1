#include "nav/localization/scan_matcher.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "nav/localization/branch_and_bound.h"
#include "nav/localization/test_world.h"

namespace corridor::nav {
namespace {

using testworld::Room;
using testworld::ScanAt;

// A scan of the test room seen from `pose`, inserted into a fresh grid at `pose`.
HitField GridOfRoom(const std::vector<Pose2>& poses) {
  HitField grid;
  for (const Pose2& pose : poses) grid.Insert(ScanAt(Room(), pose), pose);
  return grid;
}

double PositionError(const Pose2& a, const Pose2& b) { return (a.translation() - b.translation()).norm(); }

TEST(ScanMatcherTest, FindsTheScansPoseFromGuessesAroundIt) {
  const Pose2 truth{1.0, 0.5, 0.3};
  const HitField grid = GridOfRoom({truth, {2.0, 1.0, -1.0}, {0.0, 0.0, 2.0}});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-0.12, 0.12);
  std::uniform_real_distribution<double> turn(-0.1, 0.1);
  const RangeScan scan = ScanAt(Room(), truth);
  const std::vector<Eigen::Vector2f> points = VoxelFilter(scan.hits, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose2 guess{truth.x_m + offset(random), truth.y_m + offset(random), truth.yaw_rad + turn(random)};
    const ScanMatch coarse = CorrelativeMatch(grid, points, guess, SearchWindow{0.15, 0.12});
    const Pose2 refined = RefineMatch(grid, points, coarse.pose, coarse.pose, RefineOptions{1.0, 0.1, 0.1, 20});
    EXPECT_LT(PositionError(refined, truth), 0.02) << "trial " << trial;
    EXPECT_LT(std::abs(WrapAngle(refined.yaw_rad - truth.yaw_rad)), 0.01) << "trial " << trial;
  }
}

TEST(ScanMatcherTest, BranchAndBoundFindsTheScanAnywhereInTheMap) {
  const HitField grid = GridOfRoom({{1.0, 0.5, 0.3}, {3.0, 2.0, -1.0}, {-2.0, -1.0, 2.0}, {0.0, 2.0, 0.0}});
  const BranchAndBoundMatcher matcher(grid);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(-2.5, 3.0);
  std::uniform_real_distribution<double> y(-1.5, 2.5);
  std::uniform_real_distribution<double> yaw(-std::numbers::pi, std::numbers::pi);
  for (int trial = 0; trial < 10; ++trial) {
    const Pose2 truth{x(random), y(random), yaw(random)};
    const std::vector<Eigen::Vector2f> points = VoxelFilter(ScanAt(Room(), truth).hits, 0.05);
    const std::optional<ScanMatch> found = matcher.MatchEverywhere(points, 0.5);
    ASSERT_TRUE(found) << "trial " << trial;
    EXPECT_LT(PositionError(found->pose, truth), 0.08) << "trial " << trial;
    EXPECT_LT(std::abs(WrapAngle(found->pose.yaw_rad - truth.yaw_rad)), 0.03) << "trial " << trial;
  }
}

}  // namespace
}  // namespace corridor::nav
