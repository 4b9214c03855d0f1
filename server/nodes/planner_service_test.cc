#include "server/nodes/planner_service.h"

#include <gtest/gtest.h>

namespace corridor::server {
namespace {

TEST(PlannerServiceTest, TrafficMadeForAReplacedMapIsDropped) {
  const drivers::ManualClock clock;
  Executor planning("planning", clock, Schedule::kLockstep);  // SetMap, SetTraffic and has_traffic do not run on it
  PlannerService planner(planning, nav::CostmapOptions{});
  const auto first = std::make_shared<const nav::OccupancyGrid>(20, 20, 0.05, nav::Pose2{}, nav::kFreeCell);
  const auto second = std::make_shared<const nav::OccupancyGrid>(20, 20, 0.05, nav::Pose2{}, nav::kFreeCell);
  const auto cost = std::make_shared<const std::vector<float>>(400, 1.0f);
  planner.SetMap(first);
  planner.SetTraffic(cost, first.get());
  EXPECT_TRUE(planner.has_traffic());
  planner.SetMap(second);
  EXPECT_FALSE(planner.has_traffic());  // the old map's costs went with it
  // The tracker, not yet told of the new map, hands on costs of the old one: the same size, but not this map's.
  planner.SetTraffic(cost, first.get());
  EXPECT_FALSE(planner.has_traffic());
  planner.SetTraffic(cost, second.get());
  EXPECT_TRUE(planner.has_traffic());
  planner.SetTraffic(nullptr, second.get());  // nobody walking any more
  EXPECT_FALSE(planner.has_traffic());
}

}  // namespace
}  // namespace corridor::server
