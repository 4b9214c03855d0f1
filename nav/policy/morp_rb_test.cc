#include "nav/policy/morp_rb.h"
#include "nav/policy/local_navigator.h"
#include "nav/policy/reactive.h"
#include "nav/safety/obstacle_memory.h"

#include <gtest/gtest.h>

#include <random>

#include "nav/map/map_io.h"
#include "nav/planner/planner.h"
#include "testing/source_dir.h"

namespace corridor::nav {
namespace {

// Four lanes across a 0.4 m robot, left to right; a negative distance means the lane is free.
std::vector<LaneResult> Lanes(std::initializer_list<double> dead_ends) {
  std::vector<LaneResult> lanes;
  double offset = 0.15;
  for (double d : dead_ends) {
    LaneResult lane;
    lane.offset_m = offset;
    lane.dead_end = d >= 0.0;
    lane.free_distance_m = d >= 0.0 ? d : 4.0;
    lanes.push_back(lane);
    offset -= 0.1;
  }
  return lanes;
}

// A lane whose dead-end is the base-frame point (x, y).
LaneResult DeadEndAt(double offset, double x, double y) {
  LaneResult lane;
  lane.offset_m = offset;
  lane.dead_end = true;
  lane.free_distance_m = x;
  lane.point = {x, y, 0.1};
  return lane;
}

TEST(MorpRbTest, ClearLanesFollowTheWaypoint) {
  const MorpRbOptions o;
  const auto straight = MorpRb(o).Decide(Lanes({-1, -1, -1, -1}), 0.0, 0.1);
  EXPECT_EQ(straight.mode, MorpRbMode::kFollow);
  EXPECT_DOUBLE_EQ(straight.twist.linear_mps, o.max_linear_mps);
  EXPECT_DOUBLE_EQ(straight.twist.angular_rps, 0.0);
  const auto left = MorpRb(o).Decide(Lanes({-1, -1, -1, -1}), 0.4, 0.1);
  EXPECT_GT(left.twist.angular_rps, 0.0);
  EXPECT_LT(left.twist.linear_mps, o.max_linear_mps);
  const auto behind = MorpRb(o).Decide(Lanes({-1, -1, -1, -1}), -2.5, 0.1);
  EXPECT_EQ(behind.twist.linear_mps, 0.0);  // turn in place first
  EXPECT_LT(behind.twist.angular_rps, 0.0);
}

TEST(MorpRbTest, AnObstacleOnTheLeftMeansChangeLaneToTheRightAndSlowDown) {
  const MorpRbOptions o;
  const auto d = MorpRb(o).Decide(Lanes({0.7, 0.7, -1, -1}), 0.1, 0.1);
  EXPECT_EQ(d.mode, MorpRbMode::kChangeLaneRight);
  EXPECT_LT(d.twist.angular_rps, 0.0);
  EXPECT_GT(d.twist.linear_mps, 0.0);
  EXPECT_LT(d.twist.linear_mps, o.max_linear_mps);
  const auto mirrored = MorpRb(o).Decide(Lanes({-1, -1, 0.7, 0.7}), -0.1, 0.1);
  EXPECT_EQ(mirrored.mode, MorpRbMode::kChangeLaneLeft);
  EXPECT_GT(mirrored.twist.angular_rps, 0.0);
}

TEST(MorpRbTest, ABlockedWayTurnsTowardTheWaypointAndNearerMeansSlower) {
  const MorpRbOptions o;
  const auto toward_goal = MorpRb(o).Decide(Lanes({0.8, 0.8, 0.8, 0.8}), -0.3, 0.1);
  EXPECT_EQ(toward_goal.mode, MorpRbMode::kChangeLaneRight);
  const auto far = MorpRb(o).Decide(Lanes({0.9, 0.9, 0.9, 0.9}), 0.3, 0.1);
  const auto near = MorpRb(o).Decide(Lanes({0.55, 0.55, 0.55, 0.55}), 0.3, 0.1);
  EXPECT_EQ(far.mode, MorpRbMode::kChangeLaneLeft);
  EXPECT_LT(near.twist.linear_mps, far.twist.linear_mps);
}

TEST(MorpRbTest, TooCloseToPassMeansStopAndTurnAndBlindMeansStop) {
  const MorpRbOptions o;
  const auto d = MorpRb(o).Decide(Lanes({0.3, 0.3, 0.9, -1}), 0.0, 0.1);
  EXPECT_EQ(d.mode, MorpRbMode::kStopAndTurn);
  EXPECT_EQ(d.twist.linear_mps, 0.0);
  EXPECT_LT(d.twist.angular_rps, 0.0);  // the right side is freer
  std::vector<LaneResult> blind = Lanes({0.2, 0.2, 0.2, 0.2});
  for (auto& lane : blind) lane.blind = true;
  EXPECT_EQ(MorpRb(o).Decide(blind, 0.0, 0.1).twist.linear_mps, 0.0);
  EXPECT_EQ(MorpRb(o).Decide({}, 0.0, 0.1).twist.linear_mps, 0.0);
}

TEST(MorpRbTest, ItKeepsItsSideThenOvertakesBeforeTurningBack) {
  const MorpRbOptions o;
  MorpRb policy(o);
  // Blocked, the right side freer: it goes right...
  EXPECT_EQ(policy.Decide(Lanes({0.6, 0.6, 0.9, 0.9}), 0.0, 0.1).mode, MorpRbMode::kChangeLaneRight);
  // ...and stays right even when the left looks freer a frame later (no dithering).
  EXPECT_EQ(policy.Decide(Lanes({0.9, 0.9, 0.6, 0.6}), 0.0, 0.1).mode, MorpRbMode::kChangeLaneRight);
  // Clear: straight on for the overtaking distance although the waypoint is to the left.
  const MorpRbDecision overtaking = policy.Decide(Lanes({-1, -1, -1, -1}), 0.8, 0.1);
  EXPECT_EQ(overtaking.mode, MorpRbMode::kOvertake);
  EXPECT_EQ(overtaking.twist.angular_rps, 0.0);
  for (int i = 0; i < 100; ++i) policy.Decide(Lanes({-1, -1, -1, -1}), 0.8, 0.1);  // 10 s at up to 0.26 m/s
  EXPECT_EQ(policy.Decide(Lanes({-1, -1, -1, -1}), 0.8, 0.1).mode, MorpRbMode::kFollow);
}

// A straight 6 m path along x from the origin.
std::vector<Waypoint> StraightPath() {
  std::vector<Waypoint> path;
  for (int i = 0; i <= 6; ++i) path.push_back({Pose2{static_cast<double>(i), 0.0, 0.0}});
  return path;
}

TEST(LocalNavigatorTest, ClearLanesFollowThePath) {
  const LocalNavigatorOptions o;
  LocalNavigator nav(o);
  nav.SetPath(StraightPath());
  const LocalStep step = nav.Update(Pose2{1.0, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  EXPECT_FALSE(step.avoiding);
  EXPECT_EQ(step.mode, MorpRbMode::kFollow);
  EXPECT_NEAR(step.twist.linear_mps, o.follower.max_linear_mps, 1e-9);
  EXPECT_NEAR(step.twist.angular_rps, 0.0, 1e-9);
}

TEST(LocalNavigatorTest, AnObstacleOnThePathIsPassedByMorpRbWithinTheSpeedLimit) {
  const LocalNavigatorOptions o;
  LocalNavigator nav(o);
  nav.SetPath(StraightPath());
  const LocalStep step = nav.Update(Pose2{1.0, 0.0, 0.0}, Lanes({0.7, 0.7, -1, -1}), 0.1, 0.05);
  EXPECT_TRUE(step.avoiding);
  EXPECT_EQ(step.mode, MorpRbMode::kChangeLaneRight);
  EXPECT_LT(step.twist.angular_rps, 0.0);
  EXPECT_GT(step.twist.linear_mps, 0.0);
  EXPECT_LE(step.twist.linear_mps, 0.1);  // the mission's limit holds while avoiding too
  EXPECT_NEAR(step.nearest_m, 0.7, 1e-9);
}

TEST(LocalNavigatorTest, WhatTheMapShowsIsThePathsBusinessWhatItDoesNotIsMorpRbs) {
  // The robot at (1, 0) on a straight path; its two left lanes end 0.7 m ahead, at about (1.7, 0.1).
  std::vector<LaneResult> lanes = Lanes({-1, -1, -1, -1});
  lanes[0] = DeadEndAt(0.15, 0.7, 0.15);
  lanes[1] = DeadEndAt(0.05, 0.7, 0.05);
  OccupancyGrid grid(160, 60, 0.05, Pose2{-1.0, -1.5, 0.0}, kFreeCell);
  const auto costmap_with = [&](Eigen::Vector2d speck) {
    OccupancyGrid g = grid;
    g.at(*g.WorldToCell(speck)) = kOccupiedCell;
    return std::make_shared<const Costmap>(g, std::span<const Zone>{}, CostmapOptions{});
  };
  const LocalNavigatorOptions o;
  // On the map (a speck the path passes, a wall it turns before): follow the path. (The obstacle memory does not
  // keep dead-ends on the map's walls: its rule for the map's cells keeps the robot off them.)
  LocalNavigator mapped(o);
  mapped.SetPath(StraightPath(), costmap_with({1.72, 0.12}));
  const LocalStep follow = mapped.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, 0.05);
  EXPECT_FALSE(follow.avoiding);
  EXPECT_EQ(follow.mode, MorpRbMode::kFollow);
  EXPECT_NEAR(follow.nearest_m, 0.7, 1e-9);
  EXPECT_GT(follow.twist.linear_mps, 0.0);
  // Not on it (the map's speck is elsewhere, or no map): change lane.
  for (const auto& map : {costmap_with({3.0, -1.0}), std::shared_ptr<const Costmap>()}) {
    LocalNavigator unmapped(o);
    unmapped.SetPath(StraightPath(), map);
    const LocalStep avoid = unmapped.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, 0.05);
    EXPECT_TRUE(avoid.avoiding);
    EXPECT_EQ(avoid.mode, MorpRbMode::kChangeLaneRight);
  }
  // Blind lanes (too near something to measure) in front of a mapped speck 0.35 m ahead are the map's; in open
  // floor, something unseen: stop and turn.
  std::vector<LaneResult> blind = Lanes({0.2, 0.2, -1, -1});
  blind[0].blind = blind[1].blind = true;
  LaneResult& first = blind[0];
  EXPECT_TRUE(first.dead_end);
  LocalNavigator near_speck(o);
  near_speck.SetPath(StraightPath(), costmap_with({1.35, 0.1}));
  EXPECT_FALSE(near_speck.Update(Pose2{1.0, 0.0, 0.0}, blind, 1e9, 0.05).avoiding);
  LocalNavigator open_floor(o);
  open_floor.SetPath(StraightPath(), costmap_with({3.0, -1.0}));
  EXPECT_EQ(open_floor.Update(Pose2{1.0, 0.0, 0.0}, blind, 1e9, 0.05).mode, MorpRbMode::kStopAndTurn);
}

TEST(LocalNavigatorTest, AGoalItCannotGetNearerToThanAFewCentimetresIsReachedThere) {
  LocalNavigator nav(LocalNavigatorOptions{});
  std::vector<Waypoint> path = StraightPath();
  path.back().pose.yaw_rad = 0.5;
  nav.SetPath(path);
  for (double x = 1.0; x < 5.0; x += 1.0) nav.Update(Pose2{x, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  // 3 cm short of the goal with something right in front: no forward motion, and the position counts as reached.
  const std::vector<LaneResult> touching = Lanes({0.2, 0.2, 0.2, 0.2});
  EXPECT_EQ(nav.Update(Pose2{5.97, 0.0, 0.0}, touching, 1e9, 0.05).twist.linear_mps, 0.0);
  const LocalStep turn = nav.Update(Pose2{5.97, 0.0, 0.0}, touching, 1e9, 0.05);
  EXPECT_EQ(turn.twist.linear_mps, 0.0);
  EXPECT_GT(turn.twist.angular_rps, 0.0);  // to the goal's heading
  EXPECT_TRUE(nav.Update(Pose2{5.97, 0.0, 0.5}, touching, 1e9, 0.05).done);
  // 10 cm short it waits instead.
  LocalNavigator far(LocalNavigatorOptions{});
  far.SetPath(path);
  for (double x = 1.0; x < 5.0; x += 1.0) far.Update(Pose2{x, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  far.Update(Pose2{5.9, 0.0, 0.0}, touching, 1e9, 0.05);
  EXPECT_FALSE(far.Update(Pose2{5.9, 0.0, 0.5}, touching, 1e9, 0.05).done);
}

// The default world's map, Willow Garage.
std::shared_ptr<const Costmap> WillowGarage() {
  const OccupancyGrid grid = LoadMap(testing::SourceDir() / "config/worlds/willow_garage/willow-full-0.05.yaml");
  return std::make_shared<const Costmap>(grid, std::span<const Zone>{}, CostmapOptions{});
}

struct Drive {
  bool done = false;
  double driven_m = 0.0;
};

// Drives `robot` by `nav`'s commands, 15 frames a second with the same `lanes`, until it is done or `seconds` have
// passed; every pose must keep `radius_m` clear of the map's obstacles.
Drive DriveOnMap(LocalNavigator& nav, Pose2& robot, const std::vector<LaneResult>& lanes, const Costmap& map,
                 double radius_m, double seconds) {
  const double dt = 1.0 / 15.0;
  Drive drive;
  for (int i = 0; i < static_cast<int>(seconds / dt) && !drive.done; ++i) {
    const LocalStep step = nav.Update(robot, lanes, 1e9, dt);
    drive.done = step.done;
    const Pose2 next = DriveArc(robot, step.twist, dt);
    drive.driven_m += (next.translation() - robot.translation()).norm();
    robot = next;
    EXPECT_GT(map.ClearanceAt(robot.translation()), radius_m) << "touched the map at " << i;
  }
  return drive;
}

TEST(LocalNavigatorTest, ACornerOfThePathBesideTheMapsSpecksIsFollowedNotLeftForALoop) {
  // The default world's second mission: from beside the specks north of the start to a goal 0.9 m away, round a
  // corner of the path 0.25 m from the map's unknown cells. The follower's arc cuts the corner, the memory refuses it
  // for the map, and the robot used to drive on away from the path (a detour, meant for what the camera saw) and
  // loop back: 2.9 m driven in the daemon, or stuck 1 m west of the path here.
  const auto costmap = WillowGarage();
  Pose2 robot{24.39, 26.50, -0.89};
  PathOptions stood;
  stood.robot_at_start = true;
  const PlanResult plan = PlanPath(*costmap, robot.translation(), {25.0, 27.2}, std::nullopt, nullptr, stood);
  ASSERT_TRUE(plan.ok()) << plan.detail;
  LocalNavigatorOptions o;
  o.follower.max_linear_mps = 0.5;  // the daemon's
  LocalNavigator nav(o);
  nav.SetPath(plan.plan.waypoints, costmap);
  std::vector<LaneResult> lanes;  // nothing seen: the specks are not in the building
  for (double offset = 0.45; offset > -0.5; offset -= 0.1) {
    LaneResult lane;
    lane.offset_m = offset;
    lane.free_distance_m = 4.0;
    lanes.push_back(lane);
  }
  const Drive drive = DriveOnMap(nav, robot, lanes, *costmap, o.memory.robot_radius_m, 30.0);
  EXPECT_TRUE(drive.done);
  EXPECT_LT((robot.translation() - Eigen::Vector2d(25.0, 27.2)).norm(), 0.05);
  EXPECT_LT(drive.driven_m, 1.3 * plan.plan.length_m);
}

TEST(LocalNavigatorTest, BesideACornerOfTheMapATurnRefusedByTheMapIsMadeOnTheSpot) {
  // The same mission, where the daemon's robot stood for a minute (under load, after swerving north past the corner
  // for what the camera saw of the specks): facing north-north-east, the follower turning right for the goal. Its
  // arc closes in on an unknown cell to the north; the memory refused it and turned the robot left on the spot, away
  // from the map's nearer side, and the follower turned it right again, for ever.
  const auto costmap = WillowGarage();
  const std::vector<Waypoint> path = {{Pose2{24.394, 26.507, 1.616}},
                                      {Pose2{24.375, 26.925, 0.785}},
                                      {Pose2{24.675, 27.225, -0.077}},
                                      {Pose2{25.0, 27.2, -0.077}}};
  LocalNavigatorOptions o;
  o.follower.max_linear_mps = 0.5;
  LocalNavigator nav(o);
  nav.SetPath(path, costmap);
  Pose2 robot{24.318, 27.124, 1.3};
  EXPECT_TRUE(DriveOnMap(nav, robot, Lanes({-1, -1, -1, -1}), *costmap, o.memory.robot_radius_m, 20.0).done);
  EXPECT_LT((robot.translation() - Eigen::Vector2d(25.0, 27.2)).norm(), 0.05);
}

TEST(LocalNavigatorTest, ACentimetreFromTheGoalWithSomethingJustInFrontItTurnsToTheGoalsHeading) {
  // As in the daemon at the default world's first goal: 1.02 cm from the goal, which lies to the robot's side, with
  // what the bumper touched remembered across its front. The polar controller creeps a few millimetres while it
  // turns; the memory used to refuse every such turn as closing in on the points, and the robot dithered on the spot
  // (or spun round and round) until they were forgotten 30 s later.
  std::vector<Waypoint> path = {{Pose2{-0.525, 0.625, -0.872}}, {Pose2{0.0, 0.0, -0.872}}};
  LocalNavigatorOptions o;
  o.follower.max_linear_mps = 0.5;
  LocalNavigator nav(o);
  nav.SetPath(path);
  Pose2 robot{-0.010213, 0.000452, -1.6126816};
  nav.Touched(robot, /*backing=*/false);
  double turned = 0.0;
  bool done = false;
  for (int i = 0; i < 3 * 15 && !done; ++i) {
    const LocalStep step = nav.Update(robot, Lanes({-1, -1, -1, -1}), 1e9, 1.0 / 15.0);
    done = step.done;
    turned += std::abs(step.twist.angular_rps) / 15.0;
    robot = DriveArc(robot, step.twist, 1.0 / 15.0);
  }
  EXPECT_TRUE(done);
  EXPECT_NEAR(robot.yaw_rad, -0.872, o.follower.yaw_tolerance_rad + 1e-3);
  EXPECT_LT(turned, 1.0);  // the short way round: 0.74 rad
}

TEST(LocalNavigatorTest, FarFromThePathAsksForANewOne) {
  LocalNavigator nav(LocalNavigatorOptions{});
  nav.SetPath(StraightPath());
  const LocalStep step = nav.Update(Pose2{1.0, 1.5, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  EXPECT_TRUE(step.replan);
  EXPECT_EQ(step.twist.linear_mps, 0.0);
  EXPECT_EQ(step.twist.angular_rps, 0.0);
}

TEST(LocalNavigatorTest, NoHeadwayForStuckSecondsReportsTheWayBlockedOnceAndWhatBlockedIt) {
  LocalNavigatorOptions o;
  LocalNavigator nav(o);
  nav.SetPath(StraightPath());
  // Something across the whole way 0.3 m ahead of the robot at (1, 0): too close to pass, it turns on the spot.
  std::vector<LaneResult> lanes;
  for (double offset : {0.15, 0.05, -0.05, -0.15}) lanes.push_back(DeadEndAt(offset, 0.3, offset));
  const double dt = 0.05;
  int blocked_at = -1;
  int reports = 0;
  for (int i = 0; i < static_cast<int>((o.stuck_s + 1.0) / dt); ++i) {
    const LocalStep step = nav.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, dt);
    if (!step.blocked) continue;
    ++reports;
    if (blocked_at < 0) blocked_at = i;
  }
  EXPECT_EQ(reports, 1);  // and again only after another stuck_s
  EXPECT_NEAR(blocked_at * dt, o.stuck_s, 2 * dt);
  ASSERT_FALSE(nav.Blocking().empty());
  for (const Eigen::Vector2d& p : nav.Blocking()) {
    EXPECT_NEAR(p.x(), 1.3, 0.05);  // what it saw, in the world frame
    EXPECT_LT(std::abs(p.y()), 0.2);
  }
  // A new path gives stuck_s again to make headway on it; what blocked the robot is kept for paths planned meanwhile.
  nav.SetPath(StraightPath());
  EXPECT_FALSE(nav.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, dt).blocked);
  EXPECT_FALSE(nav.Blocking().empty());
}

TEST(LocalNavigatorTest, TheFirstPathAfterABlockedWayIsTurnedToOnTheSpotNotAvoidedAway) {
  LocalNavigatorOptions o;
  o.stuck_s = 1.0;
  LocalNavigator nav(o);
  nav.SetPath(StraightPath());
  // The left lanes end 0.3 m ahead, the right ones are free: MORP-RB turns right, toward the free lanes.
  std::vector<LaneResult> lanes = Lanes({-1, -1, -1, -1});
  lanes[0] = DeadEndAt(0.15, 0.3, 0.15);
  lanes[1] = DeadEndAt(0.05, 0.3, 0.05);
  bool blocked = false;
  for (int i = 0; i < 40 && !blocked; ++i) {
    const LocalStep step = nav.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, 0.05);
    EXPECT_TRUE(step.blocked || step.twist.angular_rps < 0.0);
    blocked = step.blocked;
  }
  ASSERT_TRUE(blocked);
  // The new path leads back and round to the left: the robot turns left on the spot until it heads along it...
  std::vector<Waypoint> back;
  for (int i = 0; i <= 6; ++i) back.push_back({Pose2{1.0 - 0.5 * i, 0.5 * i, 2.36}});
  nav.SetPath(back);
  double yaw = 0.0;
  for (int i = 0; i < 100 && yaw < 2.36 - o.reorient_done_rad; ++i) {
    const LocalStep step = nav.Update(Pose2{1.0, 0.0, yaw}, lanes, 1e9, 0.05);
    EXPECT_EQ(step.mode, MorpRbMode::kStopAndTurn);
    EXPECT_EQ(step.twist.linear_mps, 0.0);
    ASSERT_GT(step.twist.angular_rps, 0.0);
    yaw += step.twist.angular_rps * 0.05;
  }
  // ...then MORP-RB has the lanes again (these, which no longer turn with the robot, it turns right from).
  EXPECT_LT(nav.Update(Pose2{1.0, 0.0, yaw}, lanes, 1e9, 0.05).twist.angular_rps, 0.0);
  // A path set without a blocked report since is not turned to first.
  LocalNavigator fresh(o);
  fresh.SetPath(back);
  EXPECT_LT(fresh.Update(Pose2{1.0, 0.0, 0.0}, lanes, 1e9, 0.05).twist.angular_rps, 0.0);
}

TEST(LocalNavigatorTest, ARobotMakingHeadwayIsNeverBlockedAndForgetsWhatBlockedItAfterTheHold) {
  LocalNavigatorOptions o;
  o.stuck_s = 2.0;
  o.blocked_hold_s = 5.0;
  LocalNavigator nav(o);
  nav.SetPath(StraightPath());
  std::vector<LaneResult> wall;
  for (double offset : {0.15, 0.05, -0.05, -0.15}) wall.push_back(DeadEndAt(offset, 0.3, offset));
  bool blocked = false;
  for (int i = 0; i < 50 && !blocked; ++i) blocked = nav.Update(Pose2{1.0, 0.0, 0.0}, wall, 1e9, 0.05).blocked;
  ASSERT_TRUE(blocked);
  ASSERT_FALSE(nav.Blocking().empty());
  // Going on at 0.2 m/s (0.3 m in 1.5 s: headway) for longer than the hold.
  for (int i = 0; i < 120; ++i) {
    EXPECT_FALSE(nav.Update(Pose2{1.0 + 0.01 * i, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05).blocked);
  }
  EXPECT_TRUE(nav.Blocking().empty());
}

TEST(LocalNavigatorTest, BadStuckOptionsAreRefused) {
  LocalNavigatorOptions o;
  o.stuck_distance_m = 0.0;
  EXPECT_THROW(LocalNavigator{o}, std::invalid_argument);
  o = LocalNavigatorOptions{};
  o.blocked_cost = -1.0;
  EXPECT_THROW(LocalNavigator{o}, std::invalid_argument);
}

TEST(LocalNavigatorTest, TheFinalApproachIsThePolarControllersButStopsForWhatIsAhead) {
  LocalNavigator nav(LocalNavigatorOptions{});
  nav.SetPath(StraightPath());
  for (double x = 1.0; x < 5.0; x += 1.0) nav.Update(Pose2{x, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  // 0.5 m before the goal, slightly off the line: the polar controller steers back toward the goal pose...
  const LocalStep clear = nav.Update(Pose2{5.5, 0.05, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05);
  EXPECT_FALSE(clear.avoiding);
  EXPECT_GT(clear.twist.linear_mps, 0.0);
  EXPECT_LT(clear.twist.angular_rps, 0.0);
  // ...and with something in the way it does not swerve; it slows to what stops before it.
  const LocalStep blocked = nav.Update(Pose2{5.5, 0.05, 0.0}, Lanes({0.28, 0.28, 0.28, 0.28}), 1e9, 0.05);
  EXPECT_FALSE(blocked.avoiding);
  EXPECT_EQ(blocked.twist.linear_mps, 0.0);
  EXPECT_NEAR(blocked.twist.angular_rps, clear.twist.angular_rps, 1e-9);
}

TEST(LocalNavigatorTest, NoLanesMeansNoForwardMotion) {
  LocalNavigator nav(LocalNavigatorOptions{});
  nav.SetPath(StraightPath());
  EXPECT_EQ(nav.Update(Pose2{1.0, 0.0, 0.0}, {}, 1e9, 0.05).twist.linear_mps, 0.0);
  EXPECT_EQ(nav.Update(Pose2{2.0, 0.0, 0.0}, {}, 1e9, 0.05).twist.linear_mps, 0.0);
}

TEST(LocalNavigatorTest, AtTheGoalItIsDone) {
  LocalNavigator nav(LocalNavigatorOptions{});
  nav.SetPath(StraightPath());
  EXPECT_TRUE(nav.Update(Pose2{6.0, 0.0, 0.0}, Lanes({-1, -1, -1, -1}), 1e9, 0.05).done);
}

TEST(ObstacleMemoryTest, AnObstacleThatLeftTheViewStillStopsATurnIntoIt) {
  ObstacleMemory memory(ObstacleMemoryOptions{});
  // Seen 0.8 m ahead and 0.35 m to the right...
  memory.Update(Pose2{0, 0, 0}, {DeadEndAt(-0.35, 0.8, -0.35)}, 0.05);
  EXPECT_EQ(memory.size(), 1u);
  // ...then the robot drove 0.8 m on: the obstacle is beside it, out of the camera's view, and no lane sees it.
  const Pose2 beside{0.8, 0.0, 0.0};
  memory.Update(beside, {}, 3.0);
  EXPECT_EQ(memory.size(), 1u);
  // Turning right while driving would sweep into it: the guard bends the arc away instead, keeping the speed.
  const Twist2 guarded = memory.Guard(beside, {0.26, -0.8});
  EXPECT_NEAR(guarded.linear_mps, 0.26, 1e-9);
  EXPECT_GT(guarded.angular_rps, -0.8);
  // Driving away (left) is left alone.
  const Twist2 away{0.26, 0.5};
  EXPECT_EQ(memory.Guard(beside, away).angular_rps, away.angular_rps);
}

TEST(ObstacleMemoryTest, FreeFloorSeenPastAPointClearsItAndDistanceForgetsIt) {
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.Update(Pose2{0, 0, 0}, {DeadEndAt(0.05, 1.0, 0.05)}, 0.05);
  ASSERT_EQ(memory.size(), 1u);
  LaneResult free;
  free.offset_m = 0.05;
  free.free_distance_m = 4.0;
  memory.Update(Pose2{0, 0, 0}, {free}, 0.05);  // the person walked away: that lane now sees 4 m of floor
  EXPECT_EQ(memory.size(), 0u);
  memory.Update(Pose2{0, 0, 0}, {DeadEndAt(0.05, 1.0, 0.05)}, 0.05);
  memory.Update(Pose2{3.0, 0, 0}, {}, 0.05);  // driven past, far away
  EXPECT_EQ(memory.size(), 0u);
}

// A depth scan's points along y = `y` from x = x0 to x1 (base frame), a column every 2 cm; and a camera 0.1 m ahead
// of the base seeing 40 degrees either way out to 2 m.
std::vector<Eigen::Vector2d> ScanAlong(double y, double x0, double x1) {
  std::vector<Eigen::Vector2d> scan;
  for (double x = x0; x <= x1 + 1e-9; x += 0.02) scan.emplace_back(x, y);
  return scan;
}
const SensorView kScanView{Pose2{0.1, 0.0, 0.0}, 0.7, 2.0};

TEST(ObstacleMemoryTest, WhatTheCameraSawBesideTheLanesIsKeptClearOfOnceBesideTheRobot) {
  // The side of something 0.45 m to the left, 0.5-1.3 m ahead: in the camera's view, in no lane's.
  ObstacleMemory memory(ObstacleMemoryOptions{});
  ObstacleMemory lanes_only(ObstacleMemoryOptions{});
  memory.See(Pose2{0, 0, 0}, ScanAlong(0.45, 0.5, 1.3), kScanView);
  EXPECT_GT(memory.size(), 10u);
  EXPECT_LT(memory.size(), 20u);  // one point a cell: 0.8 m of it in 5 cm cells
  // Driven on until it is beside the robot, out of view: a turn toward it is bent away, keeping the speed.
  const Pose2 beside{0.9, 0.0, 0.0};
  memory.Update(beside, {}, 2.0);
  lanes_only.Update(beside, {}, 2.0);
  const Twist2 left{0.26, 0.8};
  const Twist2 guarded = memory.Guard(beside, left);
  EXPECT_NEAR(guarded.linear_mps, 0.26, 1e-9);
  EXPECT_LT(guarded.angular_rps, 0.8);
  EXPECT_EQ(lanes_only.Guard(beside, left).angular_rps, 0.8);     // the lanes never saw it
  EXPECT_EQ(memory.Guard(beside, {0.26, 0.0}).angular_rps, 0.0);  // driving on beside it is not driving into it
}

TEST(ObstacleMemoryTest, AScanPointSeenPastIsForgottenOneHiddenOrALowOneTheLanesSawIsNot) {
  ObstacleMemory memory(ObstacleMemoryOptions{});
  const Pose2 robot{2.0, 1.0, 0.5};
  memory.See(robot, {{1.0, 0.0}}, kScanView);
  memory.Update(robot, {DeadEndAt(0.3, 1.0, 0.3)}, 0.05);  // a step, below the scan's heights
  ASSERT_EQ(memory.size(), 2u);
  // Something nearer on the same bearing hides the point: it is kept.
  memory.See(robot, {{0.8, 0.0}}, kScanView);
  EXPECT_EQ(memory.size(), 3u);
  // Then the scan sees 1.45 m on that bearing: both scan points went (someone walked off); the step stays.
  memory.See(robot, {{1.45, 0.0}}, kScanView);
  EXPECT_EQ(memory.size(), 2u);      // the step and the new point
  memory.See(robot, {}, kScanView);  // nothing on that bearing within the scan's range
  EXPECT_EQ(memory.size(), 1u);
  // Nothing is cleared outside the view or nearer than the lanes see the floor.
  memory.See(robot, {{0.4, 0.0}, {0.5, 1.2}}, kScanView);
  memory.See(robot, {}, kScanView);
  EXPECT_EQ(memory.size(), 3u);
}

TEST(ObstacleMemoryTest, ScanPointsOnTheMapsWallsAreTheMapsNotRemembered) {
  OccupancyGrid grid(120, 60, 0.05, Pose2{-1.0, -1.5, 0.0}, kFreeCell);
  for (int x = 0; x < 120; ++x) grid.at({x, 40}) = kOccupiedCell;  // y = 0.50-0.55
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.SetMap(std::make_shared<const Costmap>(grid, std::span<const Zone>{}, CostmapOptions{}));
  memory.See(Pose2{0, 0, 0}, ScanAlong(0.5, 0.5, 1.0), kScanView);
  EXPECT_EQ(memory.size(), 0u);
  memory.See(Pose2{0, 0, 0}, ScanAlong(0.3, 0.5, 1.0), kScanView);  // something standing in front of the wall
  EXPECT_GT(memory.size(), 0u);
}

TEST(ObstacleMemoryTest, ALaneSeeingFloorBesideAScanPointLeavesItToTheScans) {
  // The side of a cylinder seen by the depth scan at (1.36, -0.39), 4 cm beside the line of the lane at -0.35, which
  // goes on past it over the floor (a scenario run lost a cylinder's side this way and drove into it).
  ObstacleMemory memory(ObstacleMemoryOptions{});
  const Pose2 robot{0, 0, 0};
  memory.See(robot, {{1.36, -0.39}}, kScanView);
  ASSERT_EQ(memory.size(), 1u);
  LaneResult beside;
  beside.offset_m = -0.35;
  beside.free_distance_m = 3.8;
  memory.Update(robot, {beside}, 0.05);
  EXPECT_EQ(memory.size(), 1u);
  // A scan that sees past it on its bearing (nothing there within its range) clears it.
  memory.See(robot, {}, kScanView);
  EXPECT_EQ(memory.size(), 0u);
}

TEST(ObstacleMemoryTest, WhatTheObstacleLayerPutOnTheCostmapIsStillRemembered) {
  // The same wall, once in the map and once only in the obstacle layer (the 3D map's cells of what the camera saw):
  // the map's wall is known without the memory, the layer's is remembered and kept clear of as seen.
  OccupancyGrid grid(120, 60, 0.05, Pose2{-1.0, -1.5, 0.0}, kFreeCell);
  std::vector<std::int8_t> layer(grid.cells().size(), kFreeCell);
  for (int x = 0; x < 120; ++x) layer[static_cast<std::size_t>(40) * 120 + x] = kOccupiedCell;  // y = 0.50-0.55
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.SetMap(std::make_shared<const Costmap>(grid, layer, std::span<const Zone>{}, CostmapOptions{}));
  memory.See(Pose2{0, 0, 0}, ScanAlong(0.5, 0.5, 1.0), kScanView);
  EXPECT_GT(memory.size(), 0u);
}

TEST(ObstacleMemoryTest, BesideAPointTheRobotMayDrivePastItButNotCurveAroundIt) {
  // A point seen 0.27 m to the left (7 cm from the footprint): a round obstacle's sample, its surface perhaps nearer.
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.See(Pose2{-1.0, 0.0, 0.0}, {{1.0, 0.27}}, kScanView);
  const Pose2 beside{0.0, 0.0, 0.0};
  memory.Update(beside, {}, 0.5);
  ASSERT_EQ(memory.size(), 1u);
  // An arc around it at the same distance never closes in, and is refused; the guard's arc ends farther from it.
  const Twist2 around{0.26, 0.26 / 0.27};
  EXPECT_TRUE(memory.Blocks(beside, around));
  const Twist2 guarded = memory.Guard(beside, around);
  EXPECT_NEAR(guarded.linear_mps, 0.26, 1e-9);
  EXPECT_LT(guarded.angular_rps, around.angular_rps);
  EXPECT_FALSE(memory.Blocks(beside, {0.26, 0.0}));  // straight on: past it
  EXPECT_FALSE(memory.Blocks(beside, {0.0, 1.0}));   // turning on the spot
  EXPECT_FALSE(memory.Blocks(beside, {0.0, 0.0}));   // standing
  EXPECT_FALSE(memory.Blocks(beside, around, /*approach=*/true));
  // 0.35 m away the arc is left alone: beside_m is the nearness where the unsampled surface may touch.
  const Pose2 farther{0.0, -0.08, 0.0};
  EXPECT_FALSE(memory.Blocks(farther, {0.26, 0.26 / 0.35}));
}

TEST(ObstacleMemoryTest, WhenEveryArcIsBlockedItTurnsInPlaceAwayFromTheNearestPoint) {
  ObstacleMemory memory(ObstacleMemoryOptions{});
  // A wall of points just ahead, nearer on the left.
  std::vector<LaneResult> wall;
  for (double y = -0.6; y <= 0.6; y += 0.1) wall.push_back(DeadEndAt(y, 0.4 + (y > 0 ? 0.0 : 0.05), y));
  memory.Update(Pose2{0, 0, 0}, wall, 0.05);
  const Twist2 t = memory.Guard(Pose2{0, 0, 0}, {0.26, 0.0});
  EXPECT_EQ(t.linear_mps, 0.0);
  EXPECT_LT(t.angular_rps, 0.0);  // away from the nearer, left side
}

TEST(ObstacleMemoryTest, TheMapsObstaclesAreKeptClearOfWithoutBeingSeen) {
  // A mapped wall along y = 0.5 (cells 0.50-0.55), the robot heading along it, 0.3 m from it.
  OccupancyGrid grid(120, 60, 0.05, Pose2{-1.0, -1.5, 0.0}, kFreeCell);
  for (int x = 0; x < 120; ++x) grid.at({x, 40}) = kOccupiedCell;
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.SetMap(std::make_shared<const Costmap>(grid, std::span<const Zone>{}, CostmapOptions{}));
  const Pose2 robot{0.0, 0.2, 0.0};
  EXPECT_FALSE(memory.Blocks(robot, {0.26, 0.0}));   // along it
  EXPECT_FALSE(memory.Blocks(robot, {0.26, -0.5}));  // away from it
  EXPECT_TRUE(memory.Blocks(robot, {0.26, 1.0}));    // a turn that would swing into it
  const Twist2 guarded = memory.Guard(robot, {0.26, 1.0});
  EXPECT_FALSE(memory.Blocks(robot, guarded));
  EXPECT_TRUE(guarded.linear_mps < 0.26 || guarded.angular_rps < 1.0);  // a gentler or slower arc
  // Backing toward it: the substitute still backs (away along another arc), it does not swap direction.
  const Pose2 facing_away{0.0, 0.2, -1.5707963};
  ASSERT_TRUE(memory.Blocks(facing_away, {-0.2, 0.0}));
  EXPECT_LT(memory.Guard(facing_away, {-0.2, 0.0}).linear_mps, 0.0);
  // Without the map nothing is known there.
  EXPECT_FALSE(ObstacleMemory(ObstacleMemoryOptions{}).Blocks(robot, {0.26, 1.0}));
}

TEST(ObstacleMemoryTest, WhenTheMapAloneRefusesEveryArcATurningCommandTurnsOnTheSpotItsOwnWay) {
  // A mapped corner ahead and to the right of the robot: a wall across x = 0.5 and one along y = -0.4.
  OccupancyGrid grid(60, 60, 0.05, Pose2{-1.5, -1.5, 0.0}, kFreeCell);
  for (int i = 0; i < 60; ++i) grid.at({40, i}) = grid.at({i, 22}) = kOccupiedCell;
  ObstacleMemory memory(ObstacleMemoryOptions{});
  memory.SetMap(std::make_shared<const Costmap>(grid, std::span<const Zone>{}, CostmapOptions{}));
  const Pose2 robot{0.2, -0.05, 0.0};
  ObstacleMemory::Blocker by = ObstacleMemory::Blocker::kNone;
  // Straight on: no arc is clear, and it turns away from the nearer side (the right).
  const Twist2 straight = memory.Guard(robot, {0.3, 0.0}, false, &by);
  EXPECT_EQ(by, ObstacleMemory::Blocker::kMap);
  EXPECT_EQ(straight.linear_mps, 0.0);
  EXPECT_GT(straight.angular_rps, 0.0);
  // Turning right: it goes on turning right, toward where it was going, rather than being turned back.
  const Twist2 right = memory.Guard(robot, {0.3, -1.0}, false, &by);
  EXPECT_EQ(by, ObstacleMemory::Blocker::kMap);
  EXPECT_EQ(right.linear_mps, 0.0);
  EXPECT_LT(right.angular_rps, 0.0);
}

TEST(ObstacleMemoryTest, WhatTheBumperTouchedIsNotDrivenIntoAgain) {
  ObstacleMemory memory(ObstacleMemoryOptions{});
  const Pose2 robot{1.0, 2.0, 0.3};
  EXPECT_FALSE(memory.Blocks(robot, {0.2, 0.0}));
  memory.Touched(robot);
  EXPECT_TRUE(memory.Blocks(robot, {0.2, 0.0}));
  EXPECT_FALSE(memory.Blocks(robot, {-0.2, 0.0}));             // backing away
  EXPECT_EQ(memory.Guard(robot, {0.2, 0.0}).linear_mps, 0.0);  // forward is refused: it turns away instead
  ObstacleMemory behind(ObstacleMemoryOptions{});
  behind.Touched(robot, /*backing=*/true);
  EXPECT_TRUE(behind.Blocks(robot, {-0.2, 0.0}));
  EXPECT_FALSE(behind.Blocks(robot, {0.2, 0.0}));
}

TEST(ReactiveTest, ClearCorridorFollowsBlockedSlowsAndTurnsAwayTooCloseStops) {
  const ReactiveOptions o;
  const Twist2 clear = ReactiveCommand({{2.0f, 0.0f}, {0.5f, 0.6f}}, 0.0, o);
  EXPECT_NEAR(clear.linear_mps, o.max_linear_mps, 1e-9);
  EXPECT_EQ(clear.angular_rps, 0.0);
  const Twist2 ahead = ReactiveCommand({{0.8f, 0.1f}}, 0.0, o);
  EXPECT_GT(ahead.linear_mps, 0.0);
  EXPECT_LT(ahead.linear_mps, o.max_linear_mps);
  EXPECT_LT(ahead.angular_rps, 0.0);  // the obstacle is left of centre: turn right
  const Twist2 close = ReactiveCommand({{0.3f, -0.1f}}, 0.0, o);
  EXPECT_EQ(close.linear_mps, 0.0);
  EXPECT_GT(close.angular_rps, 0.0);
}

TEST(StoppingTest, TheSpeedForAFreeDistanceAlwaysStopsWithinItOverRandomCases) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> free(0.0, 5.0);
  std::uniform_real_distribution<double> decel(0.2, 2.0);
  std::uniform_real_distribution<double> reaction(0.0, 0.3);
  for (int i = 0; i < 1000; ++i) {
    const StoppingModel m{decel(rng), reaction(rng), 0.1};
    const double d = free(rng);
    const double v = SpeedForFreeDistance(d, m);
    EXPECT_GE(v, 0.0);
    if (d > m.margin_m) {
      EXPECT_NEAR(StoppingDistance(v, m), d, 1e-9);  // the inverse, exactly at the limit
      EXPECT_FALSE(NeedsProtectiveStop(d + 1e-6, v, m));
    } else {
      EXPECT_EQ(v, 0.0);
      EXPECT_TRUE(NeedsProtectiveStop(d, 0.0, m));  // already inside the margin: stay stopped
    }
    EXPECT_TRUE(NeedsProtectiveStop(d - 0.01, v + 0.05, m));
  }
}

}  // namespace
}  // namespace corridor::nav
