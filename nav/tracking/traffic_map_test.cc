#include "nav/tracking/traffic_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "nav/planner/planner.h"

namespace corridor::nav {
namespace {

// An empty 10 m room with walls round it.
OccupancyGrid TrafficRoom() {
  OccupancyGrid grid(200, 200, 0.05, Pose2{0.0, 0.0, 0.0}, kFreeCell);
  for (int i = 0; i < 200; ++i) {
    for (const int j : {0, 199}) {
      grid.at({i, j}) = kOccupiedCell;
      grid.at({j, i}) = kOccupiedCell;
    }
  }
  return grid;
}

TrackedObject Walker(const Eigen::Vector2d& at, const Eigen::Vector2d& velocity) {
  TrackedObject o;
  o.position = at;
  o.velocity = velocity;
  o.radius_m = 0.2;
  o.moving = true;
  return o;
}

// Someone paces along x = 5 between y = 3 and y = 7 for `seconds`, seen at 10 Hz.
void Pace(TrafficMap& traffic, double seconds) {
  for (int k = 0; k <= static_cast<int>(seconds * 10.0); ++k) {
    const double t = 0.1 * k;
    const double phase = std::fmod(0.8 * t, 8.0);
    const double y = phase < 4.0 ? 3.0 + phase : 11.0 - phase;
    traffic.Add(t, {Walker({5.0, y}, {0.0, phase < 4.0 ? 0.8 : -0.8})});
  }
}

// The largest distance from x = 5 of the path's points beside the pacing (3 < y < 7), and the smallest.
std::pair<double, double> Beside(const Plan& plan) {
  double nearest = 1e9;
  double farthest = 0.0;
  for (const Eigen::Vector2d& p : plan.dense) {
    if (p.y() <= 3.0 || p.y() >= 7.0) continue;
    nearest = std::min(nearest, std::abs(p.x() - 5.0));
    farthest = std::max(farthest, std::abs(p.x() - 5.0));
  }
  return {nearest, farthest};
}

TEST(TrafficMapTest, PlansKeepOutOfTheWayPeopleWalkUntilItFades) {
  const OccupancyGrid room = TrafficRoom();
  const Costmap costmap(room, {}, CostmapOptions{});
  TrafficOptions options;
  TrafficMap traffic(room, options);
  Pace(traffic, 20.0);
  const Eigen::Vector2d start(5.0, 1.0);
  const Eigen::Vector2d goal(5.0, 9.0);

  const PlanResult straight = PlanPath(costmap, start, goal);
  ASSERT_TRUE(straight.ok());
  EXPECT_LT(Beside(straight.plan).second, 0.1) << "without the traffic the way is straight along the walk";

  const std::vector<float> cost = traffic.StepCost(20.0);
  PathOptions with_traffic;
  with_traffic.extra_cost = cost;
  const PlanResult around = PlanPath(costmap, start, goal, std::nullopt, nullptr, with_traffic);
  ASSERT_TRUE(around.ok());
  EXPECT_GT(Beside(around.plan).first, options.lane_half_width_m - 0.05) << "the plan walks along their way";
  EXPECT_TRUE(PathsDiverge(around.plan.dense, straight.plan.dense, 10.0, 0.4));
  EXPECT_FALSE(PathsDiverge(straight.plan.dense, straight.plan.dense, 10.0, 0.01));

  // Long after they have gone, the straight way is the best again.
  PathOptions faded;
  const std::vector<float> later = traffic.StepCost(20.0 + 12.0 * options.memory_s);
  faded.extra_cost = later;
  const PlanResult again = PlanPath(costmap, start, goal, std::nullopt, nullptr, faded);
  ASSERT_TRUE(again.ok());
  EXPECT_LT(Beside(again.plan).second, 0.1);
}

TEST(TrafficMapTest, OnlyWalkersMakeTrafficItFadesAndBadInputIsRefused) {
  const OccupancyGrid room = TrafficRoom();
  TrafficMap traffic(room, TrafficOptions{});
  TrackedObject standing = Walker({5.0, 5.0}, {0.0, 0.0});
  standing.moving = false;
  traffic.Add(1.0, {standing, Walker({-3.0, 5.0}, {0.8, 0.0})});  // the second is off the map
  for (const float c : traffic.StepCost(1.0)) ASSERT_EQ(c, 0.0f);
  EXPECT_TRUE(traffic.Empty(1.0));
  traffic.Add(2.0, {Walker({5.0, 5.0}, {0.8, 0.0})});
  EXPECT_FALSE(traffic.Empty(2.0));
  EXPECT_TRUE(traffic.Empty(2.0 + 10.0 * TrafficOptions{}.memory_s));

  TrafficOptions bad;
  bad.memory_s = 0.0;
  EXPECT_THROW(TrafficMap(room, bad), std::invalid_argument);
  const Costmap costmap(room, {}, CostmapOptions{});
  const std::vector<float> wrong(10, 0.0f);
  EXPECT_THROW(AStar(costmap, {1.0, 1.0}, {8.0, 8.0}, nullptr, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
