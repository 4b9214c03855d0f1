#include "nav/mission/goal_check.h"

#include <gtest/gtest.h>

#include <cmath>

namespace corridor::nav {
namespace {

// A 10 x 10 m room at 0.1 m: free inside, a wall along x = 5, a keep-out zone over x 7..9, y 7..9.
OccupancyGrid WalledRoom() {
  OccupancyGrid grid(100, 100, 0.1, Pose2{}, kFreeCell);
  for (int y = 0; y < 100; ++y) grid.at({50, y}) = kOccupiedCell;
  return grid;
}

Costmap RoomCostmap() {
  const Zone keep_out{"z1", "store room", ZoneKind::kKeepOut, {{7, 7}, {9, 7}, {9, 9}, {7, 9}}, 0.0};
  return Costmap(WalledRoom(), std::vector<Zone>{keep_out}, CostmapOptions{});
}

MissionGoal At(double x, double y, const std::string& floor = "") {
  MissionGoal g;
  g.pose = {x, y, 0.0};
  g.floor = floor;
  return g;
}

// Floors L1 (this map, "room") and L2 ("upper": the same room), one lift between them.
Building RoomFloors() {
  Building b;
  b.floors = {{"L1", "room"}, {"L2", "upper"}, {"L3", "roof"}};
  Lift lift;
  lift.id = "east";
  lift.stops = {{"L1", {"east/L1", {2.0, 0.0}, {2.0, 1.0}}, {1.0, 0.5, 0.0}},
                {"L2", {"east/L2", {2.0, 0.0}, {2.0, 1.0}}, {1.0, 0.5, 0.0}}};
  b.lifts = {lift};
  return b;
}

struct Check {
  Costmap costmap = RoomCostmap();
  Building building = RoomFloors();
  bool lifts = true;
  GoalCheckResult operator()(std::vector<MissionGoal> goals) const {
    GoalCheckInputs in;
    in.costmap = &costmap;
    in.building = &building;
    in.map = "room";
    in.grid_of = [](const std::string& map) {
      return map == "upper" ? std::make_shared<const OccupancyGrid>(WalledRoom()) : nullptr;
    };
    in.lift_controller = lifts;
    return CheckMissionGoals(std::move(goals), in);
  }
};

MissionRefusal Refusal(const GoalCheckResult& result) {
  EXPECT_TRUE(std::holds_alternative<MissionRefusal>(result));
  return std::holds_alternative<MissionRefusal>(result) ? std::get<MissionRefusal>(result) : MissionRefusal{};
}

TEST(GoalCheckTest, FreeGoalsPassAsTheyAre) {
  const auto result = Check{}({At(1, 1), At(3, 8)});
  ASSERT_TRUE(std::holds_alternative<std::vector<MissionGoal>>(result));
  EXPECT_EQ(std::get<std::vector<MissionGoal>>(result).size(), 2u);
}

TEST(GoalCheckTest, AGoalOffTheMapInAWallOrInAKeepOutZoneIsRefusedByNumber) {
  const Check check;
  MissionRefusal r = Refusal(check({At(1, 1), At(12, 1)}));
  EXPECT_EQ(r.reason, GoalRefusal::kOutsideMap);
  EXPECT_EQ(r.goal, 1u);
  EXPECT_EQ(Describe(r, "waypoints[1]"), "waypoints[1] is outside the map");
  r = Refusal(check({At(5.02, 3)}));
  EXPECT_EQ(r.reason, GoalRefusal::kOccupied);
  EXPECT_EQ(r.goal, 0u);
  r = Refusal(check({At(1, 1), At(2, 2), At(8, 8)}));
  EXPECT_EQ(r.reason, GoalRefusal::kInKeepOut);
  EXPECT_EQ(r.goal, 2u);
  EXPECT_STREQ(ToString(r.reason), "goal_in_keep_out");
}

TEST(GoalCheckTest, AnUndockingGoalIsNotChecked) {
  MissionGoal undock = At(5.0, 3.0);  // in the wall: a dock is an obstacle on the map
  undock.action = GoalAction::kUndock;
  EXPECT_TRUE(std::holds_alternative<std::vector<MissionGoal>>(Check{}({undock})));
}

TEST(GoalCheckTest, GoalsOnAnotherFloorAreCheckedOnItsMapAndRoutedThroughALift) {
  const Check check;
  const auto result = check({At(3, 3, "L2")});
  ASSERT_TRUE(std::holds_alternative<std::vector<MissionGoal>>(result));
  const auto& goals = std::get<std::vector<MissionGoal>>(result);
  ASSERT_EQ(goals.size(), 2u);  // the ride (from the lift's lobby here), then the goal there
  EXPECT_EQ(goals[0].action, GoalAction::kRideLift);
  EXPECT_EQ(goals[0].ride_to, "L2");
  EXPECT_EQ(Refusal(check({At(5.0, 3, "L2")})).reason, GoalRefusal::kOccupied);  // in L2's wall
  EXPECT_EQ(Refusal(check({At(3, 3, "L9")})).reason, GoalRefusal::kUnknownFloor);
  EXPECT_EQ(Refusal(check({At(3, 3, "L3")})).reason, GoalRefusal::kOutsideMap);  // its map cannot be had
  Check no_lifts;
  no_lifts.lifts = false;
  const MissionRefusal r = Refusal(no_lifts({At(3, 3, "L2")}));
  EXPECT_EQ(r.reason, GoalRefusal::kNoLiftController);
  EXPECT_FALSE(r.goal);
}

TEST(GoalCheckTest, GoalsOnFloorsFromAMapThatIsNoFloorAreRefused) {
  Check check;
  check.building.floors = {{"L2", "upper"}};
  EXPECT_EQ(Refusal(check({At(3, 3, "L2")})).reason, GoalRefusal::kNotOnFloor);
}

}  // namespace
}  // namespace corridor::nav
