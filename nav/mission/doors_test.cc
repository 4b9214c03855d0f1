#include "nav/mission/doors.h"

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

// A corridor along x with doors across it at x = 3 and x = 6, and one beside it that the path does not cross.
const std::vector<Door> kDoors = {
    {"far", {6.0, -1.0}, {6.0, 1.0}}, {"near", {3.0, -1.0}, {3.0, 1.0}}, {"aside", {4.0, 2.0}, {5.0, 2.0}}};
const std::vector<Eigen::Vector2d> kPath = {{0.0, 0.0}, {4.0, 0.0}, {10.0, 0.0}};

TEST(DoorsTest, ThePathCrossesItsDoorsInOrderAtTheirDistanceFromTheEnd) {
  const auto crossings = DoorsOnPath(kPath, kDoors);
  ASSERT_EQ(crossings.size(), 2u);
  EXPECT_EQ(crossings[0].door, "near");
  EXPECT_NEAR(crossings[0].from_end_m, 7.0, 1e-9);
  EXPECT_EQ(crossings[1].door, "far");
  EXPECT_NEAR(crossings[1].from_end_m, 4.0, 1e-9);
  EXPECT_TRUE(DoorsOnPath({{0.0, 0.0}}, kDoors).empty());
  EXPECT_THROW(Validate(DoorOptions{.request_m = 0.5, .hold_m = 0.6}), std::invalid_argument);
}

TEST(DoorsTest, AskedAheadHeldShortUntilOpenThenReleasedOncePassed) {
  DoorKeeper keeper{DoorOptions{}};
  std::vector<DoorRequest> requests;
  keeper.SetPath(DoorsOnPath(kPath, kDoors), requests);
  DoorReports reports;
  // 10 m from the end: "near" (7 m from the end) is 3 m ahead, within request_m: asked for.
  DoorKeeper::Step step = keeper.Update(0.0, 10.0, reports, requests);
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].door, "near");
  EXPECT_TRUE(requests[0].open);
  EXPECT_FALSE(step.hold);
  // 1.6 m (hold_m) before it, still closed: held.
  step = keeper.Update(2.0, 7.6, reports, requests);
  EXPECT_TRUE(step.hold);
  EXPECT_EQ(step.waiting_for, "near");
  EXPECT_EQ(requests.size(), 1u);  // asked once
  // Open: on it goes, and "far", 3.6 m ahead now, is asked for.
  reports["near"] = {DoorStatus::kOpen, ""};
  step = keeper.Update(3.0, 7.6, reports, requests);
  EXPECT_FALSE(step.hold);
  ASSERT_EQ(requests.size(), 2u);
  EXPECT_EQ(requests[1].door, "far");
  // Through "near" and 0.8 m on: released.
  step = keeper.Update(5.0, 6.1, reports, requests);
  ASSERT_EQ(requests.size(), 3u);
  EXPECT_EQ(requests[2].door, "near");
  EXPECT_FALSE(requests[2].open);
  // The mission ends: what is still asked for is released.
  keeper.ReleaseAll(requests);
  ASSERT_EQ(requests.size(), 4u);
  EXPECT_EQ(requests[3].door, "far");
  EXPECT_FALSE(requests[3].open);
}

TEST(DoorsTest, ARefusalOrATimeoutEndsTheMissionBeforeTheDoor) {
  DoorKeeper keeper{DoorOptions{.timeout_s = 10.0}};
  std::vector<DoorRequest> requests;
  keeper.SetPath(DoorsOnPath(kPath, kDoors), requests);
  DoorReports reports{{"near", {DoorStatus::kRefused, "the door is locked"}}};
  DoorKeeper::Step step = keeper.Update(0.0, 10.0, reports, requests);
  ASSERT_TRUE(step.failure);
  EXPECT_EQ(*step.failure, "door near refused to open: the door is locked");
  DoorKeeper slow{DoorOptions{.timeout_s = 10.0}};
  slow.SetPath(DoorsOnPath(kPath, kDoors), requests);
  reports["near"] = {DoorStatus::kOpening, ""};
  EXPECT_FALSE(slow.Update(0.0, 10.0, reports, requests).failure);
  step = slow.Update(10.5, 7.6, reports, requests);
  ASSERT_TRUE(step.failure);
  EXPECT_NE(step.failure->find("did not open within 10 s"), std::string::npos);
}

TEST(DoorsTest, ANewPathThatNoLongerCrossesADoorReleasesIt) {
  DoorKeeper keeper{DoorOptions{}};
  std::vector<DoorRequest> requests;
  keeper.SetPath(DoorsOnPath(kPath, kDoors), requests);
  keeper.Update(0.0, 10.0, {}, requests);
  keeper.SetPath({}, requests);
  ASSERT_EQ(requests.size(), 2u);
  EXPECT_EQ(requests[1].door, "near");
  EXPECT_FALSE(requests[1].open);
}

TEST(DoorsTest, WhatWasMappedOnADoorsLineIsClearedFromTheObstacleLayer) {
  const OccupancyGrid grid(100, 100, 0.05, Pose2{}, kFreeCell);  // 5 x 5 m
  std::vector<std::int8_t> layer(100 * 100, kFreeCell);
  const auto at = [&](double x, double y) -> std::int8_t& {
    const auto c = *grid.WorldToCell({x, y});
    return layer[static_cast<std::size_t>(c.y) * 100 + c.x];
  };
  at(2.0, 2.5) = kOccupiedCell;  // the closed panel, seen
  at(3.0, 2.5) = kOccupiedCell;  // a box beyond it
  ClearDoors(grid, {{"d", {2.0, 2.0}, {2.0, 3.0}}}, 0.1, layer);
  EXPECT_EQ(at(2.0, 2.5), kFreeCell);
  EXPECT_EQ(at(3.0, 2.5), kOccupiedCell);
}

}  // namespace
}  // namespace corridor::nav
