#include "server/nodes/planner_service.h"

#include <gtest/gtest.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

std::shared_ptr<const nav::OccupancyGrid> FreeGrid() {
  return std::make_shared<const nav::OccupancyGrid>(20, 20, 0.05, nav::Pose2{}, nav::kFreeCell);
}

MapInUse InUse(std::string name, std::shared_ptr<const nav::OccupancyGrid> grid) {
  MapInUse map;
  map.name = std::move(name);
  map.grid = std::move(grid);
  return map;
}

class PlannerServiceTest : public ::testing::Test {
 protected:
  // What the planner was told, taken on its executor.
  void Publish(const MapInUse& map) {
    bus_.Get(topics::kMapInUse).Publish(map);
    planning_.Poll();
  }
  void Traffic(const std::shared_ptr<const nav::OccupancyGrid>& map, std::shared_ptr<const std::vector<float>> cost) {
    bus_.Get(topics::kTrafficLayer).Publish(TrafficLayer{map, std::move(cost)});
    planning_.Poll();
  }
  void Exploring(std::shared_ptr<const nav::OccupancyGrid> grid) {
    bus_.Get(topics::kExploringMap).Publish(ExploringMap{std::move(grid)});
    planning_.Poll();
  }

  const drivers::ManualClock clock_;
  Executor planning_{"planning", clock_, Schedule::kLockstep};
  Bus bus_;
  const std::shared_ptr<const nav::OccupancyGrid> first_ = FreeGrid();
  const std::shared_ptr<const nav::OccupancyGrid> second_ = FreeGrid();
  const std::shared_ptr<const std::vector<float>> cost_ = std::make_shared<const std::vector<float>>(400, 1.0f);
};

TEST_F(PlannerServiceTest, TrafficMadeForAReplacedMapIsDropped) {
  PlannerService planner(planning_, bus_, nav::CostmapOptions{});
  Publish(InUse("first", first_));
  Traffic(first_, cost_);
  EXPECT_TRUE(planner.has_traffic());
  Publish(InUse("second", second_));
  EXPECT_FALSE(planner.has_traffic());  // the old map's costs went with it
  // The tracker, not yet told of the new map, hands on costs of the old one: the same size, but not this map's.
  Traffic(first_, cost_);
  EXPECT_FALSE(planner.has_traffic());
  Traffic(second_, cost_);
  EXPECT_TRUE(planner.has_traffic());
  Traffic(second_, nullptr);  // nobody walking any more
  EXPECT_FALSE(planner.has_traffic());
}

TEST_F(PlannerServiceTest, AZoneDrawnKeepsTheTrafficAndChangesTheVersion) {
  Publish(InUse("first", first_));  // before the planner exists: the topic is latched
  PlannerService planner(planning_, bus_, nav::CostmapOptions{});
  planning_.Poll();
  Traffic(first_, cost_);
  const std::uint64_t before = planner.version();
  MapInUse zoned = InUse("first", first_);
  nav::Zone zone;
  zone.polygon = {{0.1, 0.1}, {0.5, 0.1}, {0.5, 0.5}};
  zoned.zones.push_back(zone);
  Publish(zoned);
  EXPECT_GT(planner.version(), before);
  EXPECT_TRUE(planner.has_traffic());  // the same map: where people walk still holds
}

TEST_F(PlannerServiceTest, WhileExploringPlansGoOnTheMapBeingBuiltThenBackOnTheMapInUseWithItsLayers) {
  PlannerService planner(planning_, bus_, nav::CostmapOptions{});
  Publish(InUse("first", first_));
  Traffic(first_, cost_);
  Exploring(second_);
  EXPECT_FALSE(planner.has_traffic());  // the map being built has none
  Exploring(nullptr);
  EXPECT_TRUE(planner.has_traffic());  // the map in use's, still on its topic
}

}  // namespace
}  // namespace corridor::server
