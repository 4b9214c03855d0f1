#include "nav/planner/frontiers.h"

#include <vector>

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

// Two 4 x 4 m rooms side by side at 5 cm (x from 0 to 8, y from 0 to 4), walled, joined by a 1 m door in the middle
// wall (x = 4, y from 1.5 to 2.5). `seen_right`: whether the right room is known, or still unknown beyond the door.
OccupancyGrid TwoRooms(bool seen_right) {
  OccupancyGrid map(164, 84, 0.05, Pose2{-0.1, -0.1, 0.0}, kUnknownCell);
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      const Eigen::Vector2d p = map.CellCenter({x, y});
      const bool wall = p.x() < 0.0 || p.y() < 0.0 || p.x() > 8.0 || p.y() > 4.0 ||
                        (std::abs(p.x() - 4.0) < 0.05 && (p.y() < 1.5 || p.y() > 2.5));
      const bool outside = p.x() < -0.05 || p.y() < -0.05 || p.x() > 8.05 || p.y() > 4.05;
      if (outside) continue;
      if (wall) {
        map.at({x, y}) = kOccupiedCell;
      } else if (p.x() < 4.0 || seen_right) {
        map.at({x, y}) = kFreeCell;
      }
    }
  }
  return map;
}

TEST(FrontiersTest, TheDoorToTheUnknownRoomIsTheNextGoal) {
  const OccupancyGrid map = TwoRooms(false);
  const std::optional<FrontierGoal> goal = NextFrontierGoal(map, {1.0, 2.0}, {});
  ASSERT_TRUE(goal);
  EXPECT_EQ(goal->frontiers, 1);
  // In the left room, within sight of the doorway and clear of the walls.
  EXPECT_LT(goal->position.x(), 4.0);
  EXPECT_GT(goal->position.x(), 4.0 - 1.6);
  EXPECT_NEAR(goal->position.y(), 2.0, 0.6);
  EXPECT_GT(goal->path_m, 1.0);
  EXPECT_LT(goal->path_m, 3.5);
}

TEST(FrontiersTest, AGoalGivenUpIsNotOfferedAgainAndAMappedBuildingHasNone) {
  const OccupancyGrid map = TwoRooms(false);
  const std::optional<FrontierGoal> first = NextFrontierGoal(map, {1.0, 2.0}, {});
  ASSERT_TRUE(first);
  const std::vector<Eigen::Vector2d> given_up{first->position};
  const std::optional<FrontierGoal> second = NextFrontierGoal(map, {1.0, 2.0}, given_up);
  ASSERT_TRUE(second);
  EXPECT_GT((second->position - first->position).norm(), 0.5);
  // Both rooms known: nothing left to explore. A robot off the map has nowhere to go either.
  EXPECT_FALSE(NextFrontierGoal(TwoRooms(true), {1.0, 2.0}, {}));
  EXPECT_FALSE(NextFrontierGoal(map, {50.0, 2.0}, {}));
}

TEST(FrontiersTest, AClosedRoomAndSmallGapsInAWallAreNoFrontier) {
  // The left room alone, walled all round; a few unknown cells behind a 10 cm gap in its east wall (a wall's hits
  // missed by the rays) are smaller than a frontier worth a drive.
  OccupancyGrid map(84, 84, 0.05, Pose2{-0.1, -0.1, 0.0}, kOccupiedCell);
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      const Eigen::Vector2d p = map.CellCenter({x, y});
      if (p.x() > 0.0 && p.x() < 4.0 && p.y() > 0.0 && p.y() < 4.0) map.at({x, y}) = kFreeCell;
      if (p.x() > 4.0 && p.y() > 1.95 && p.y() < 2.05) map.at({x, y}) = kUnknownCell;
    }
  }
  EXPECT_FALSE(NextFrontierGoal(map, {2.0, 2.0}, {}));
}

}  // namespace
}  // namespace corridor::nav
