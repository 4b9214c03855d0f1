#include "nav/ground/laser_lanes.h"

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

MorpOptions TenLanes() {
  MorpOptions o;
  o.span_m = 1.0;
  o.lane_width_m = 0.1;
  o.max_range_m = 4.0;
  return o;
}

TEST(LaserLanesTest, LanesAreMorpsLanes) {
  LaserLanes lanes(TenLanes(), 0.2);
  const std::vector<LaneResult>& out = lanes.Process({});
  ASSERT_EQ(out.size(), 10u);
  const std::vector<double> offsets = LaneOffsets(TenLanes());
  for (std::size_t j = 0; j < out.size(); ++j) {
    EXPECT_DOUBLE_EQ(out[j].offset_m, offsets[j]);
    EXPECT_FALSE(out[j].dead_end);
    EXPECT_FALSE(out[j].blind);
    EXPECT_DOUBLE_EQ(out[j].free_distance_m, 4.0);
  }
}

TEST(LaserLanesTest, EachLaneEndsAtItsNearestHitAhead) {
  LaserLanes lanes(TenLanes(), 0.2);
  // A wall at 2 m across the left half, a post at 0.8 m in the second lane from the right, and hits the lanes do not
  // hold: behind the robot, beside the span, beyond the range.
  std::vector<Eigen::Vector2f> hits;
  for (float y = 0.01f; y < 0.5f; y += 0.02f) hits.emplace_back(2.0f, y);
  hits.emplace_back(0.8f, -0.35f);
  hits.emplace_back(1.5f, -0.35f);
  hits.emplace_back(-0.3f, -0.05f);
  hits.emplace_back(1.0f, -0.7f);
  hits.emplace_back(4.5f, -0.05f);
  const std::vector<LaneResult>& out = lanes.Process(hits);
  for (int j = 0; j < 5; ++j) {
    EXPECT_TRUE(out[j].dead_end) << j;
    EXPECT_NEAR(out[j].free_distance_m, 2.0, 1e-6) << j;
    EXPECT_NEAR(out[j].point.z(), 0.2, 1e-9);
  }
  for (int j = 5; j < 10; ++j) {
    if (j == 8) continue;
    EXPECT_FALSE(out[j].dead_end) << j;
    EXPECT_DOUBLE_EQ(out[j].free_distance_m, 4.0) << j;
  }
  EXPECT_TRUE(out[8].dead_end);
  EXPECT_NEAR(out[8].free_distance_m, 0.8, 1e-6);
  EXPECT_NEAR(out[8].point.y(), -0.35, 1e-6);
  // The nearest dead-end in front of a 0.3 m half-width footprint is the post's.
  EXPECT_NEAR(NearestDeadEnd(out, 0.4), 0.8, 1e-6);
  EXPECT_NEAR(NearestDeadEnd(out, 0.3), 2.0, 1e-6);
}

TEST(LaserLanesTest, AWallRunningBesideTheRobotBetweenTwoLanesIsNoDeadEndAhead) {
  LaserLanes lanes(TenLanes(), 0.2);
  // A corridor 0.6 m wide: walls 0.3 m either side, between the lines of lanes +-0.25 and +-0.35.
  std::vector<Eigen::Vector2f> walls;
  for (float x = 0.05f; x < 4.0f; x += 0.02f) {
    walls.emplace_back(x, 0.3f);
    walls.emplace_back(x, -0.3f);
  }
  for (const LaneResult& lane : lanes.Process(walls)) EXPECT_FALSE(lane.dead_end) << lane.offset_m;
  // Nearer the centre than that, the lane beside the wall ends where it begins.
  walls.emplace_back(0.3f, 0.26f);
  EXPECT_NEAR(lanes.Process(walls)[2].free_distance_m, 0.3, 1e-6);
}

TEST(LaserLanesTest, EachScanStartsClear) {
  LaserLanes lanes(TenLanes(), 0.2);
  const std::vector<Eigen::Vector2f> wall{{1.0f, 0.0f}, {1.0f, 0.05f}, {1.0f, -0.05f}};
  EXPECT_TRUE(lanes.Process(wall)[5].dead_end);
  EXPECT_FALSE(lanes.Process({})[5].dead_end);
}

TEST(LaserLanesTest, RefusesAnUnusableLayout) {
  MorpOptions o = TenLanes();
  o.span_m = 0.0;
  EXPECT_THROW(LaserLanes(o, 0.2), std::invalid_argument);
  o = TenLanes();
  o.max_range_m = -1.0;
  EXPECT_THROW(LaserLanes(o, 0.2), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
