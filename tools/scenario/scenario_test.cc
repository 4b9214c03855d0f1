#include "tools/scenario/scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace corridor::scenario {
namespace {

// The CI scenario: one seeded run of the paper's protocol with people and unmapped obstacles. corridor's navigator,
// as the daemon runs it on a robot without a laser (tracking people in the camera's view), must reach the goal
// without touching anything.
TEST(ScenarioTest, ASeededRunAmongPeopleAndObstaclesReachesItsGoalWithoutCollision) {
  ScenarioOptions options;
  options.seed = 7;
  options.pedestrians = 3;
  options.static_obstacles = 4;
  const Layout layout = MakeLayout(options, 0, 0);
  EXPECT_EQ(layout.routes.size(), 3u);
  EXPECT_EQ(layout.world.obstacles.size(), 4u);
  const double distance = (layout.goal - layout.start.translation()).norm();
  EXPECT_GE(distance, 7.0);
  EXPECT_LE(distance, 11.0);
  const RunResult result = RunOnce(layout, Policy::kMorpRb, options);
  EXPECT_EQ(ToString(result.outcome), std::string("success")) << result.collided_with;
  EXPECT_GT(result.depth_ms.size(), 50u);  // it drove on depth frames
}

// ASNS's fuzzy controllers (mission.policy flmc) drive the same CI scenario through the daemon's graph until the
// mission says it arrived, within 5 cm of the goal (ASNS's Table 8).
TEST(ScenarioTest, TheFuzzyControllersArriveWithin5CentimetresAmongPeopleAndObstacles) {
  ScenarioOptions options;
  options.seed = 7;
  options.pedestrians = 3;
  options.static_obstacles = 4;
  options.until_arrived = true;
  const RunResult result = RunOnce(MakeLayout(options, 0, 0), Policy::kFlmc, options);
  EXPECT_EQ(ToString(result.outcome), std::string("success")) << result.collided_with;
  ASSERT_TRUE(result.final_error_m.has_value());
  EXPECT_LE(*result.final_error_m, 0.05);
  EXPECT_GT(result.depth_ms.size(), 50u);
}

// ASNS's three settings and obstacle sizes: a corridor, an open hall, rooms; low, medium and large obstacles.
TEST(ScenarioTest, ASNSsSettingsAreACorridorAHallAndRoomsWithObstaclesOfTheirSize) {
  ScenarioOptions options;
  options.seed = 3;
  options.static_obstacles = 3;
  const auto extent = [](const Layout& layout) {
    const nav::OccupancyGrid& map = layout.map;
    return std::pair{std::min(map.width(), map.height()) * map.resolution_m(),
                     std::max(map.width(), map.height()) * map.resolution_m()};
  };
  options.setting = SettingKind::kCorridor;
  options.obstacle_size = ObstacleSize::kLow;
  Layout layout = MakeLayout(options, 0, 0);
  EXPECT_LE(extent(layout).first, 3.1);
  EXPECT_GE(extent(layout).second, 16.0);
  EXPECT_GE((layout.goal - layout.start.translation()).norm(), 7.0);
  ASSERT_FALSE(layout.world.obstacles.empty());
  for (const auto& o : layout.world.obstacles) {
    EXPECT_DOUBLE_EQ(o.height_m, 0.15);
    EXPECT_DOUBLE_EQ(o.size_m, 0.15);
  }
  options.setting = SettingKind::kOpen;
  options.obstacle_size = ObstacleSize::kLarge;
  layout = MakeLayout(options, 0, 0);
  EXPECT_GE(extent(layout).first, 25.0);
  for (const auto& o : layout.world.obstacles) EXPECT_DOUBLE_EQ(o.height_m, 1.2);
  options.setting = SettingKind::kRoom;
  layout = MakeLayout(options, 0, 0);
  EXPECT_GE(extent(layout).first, 12.0);
  EXPECT_LE(extent(layout).second, 15.1);
  EXPECT_EQ(ParseSettingKind("hall"), std::nullopt);
  EXPECT_EQ(ParseObstacleSize("medium"), ObstacleSize::kMedium);
}

// ASNS's robot: its stereo camera (three textured views matched as two pairs, fused and filtered over posed frames:
// MMSVF, the multi-view node in the graph) and the fuzzy controllers, through the same graph, reach the goal of the
// same scenario.
TEST(ScenarioTest, AStereoCameraAndTheFuzzyControllersReachTheGoalAmongPeopleAndObstacles) {
  ScenarioOptions options;
  options.seed = 7;
  options.pedestrians = 3;
  options.static_obstacles = 4;
  options.stereo = true;
  options.mmsvf = true;
  const RunResult result = RunOnce(MakeLayout(options, 0, 0), Policy::kFlmc, options);
  EXPECT_EQ(ToString(result.outcome), std::string("success")) << result.collided_with;
  EXPECT_GT(result.depth_ms.size(), 50u);
}

// Five people pacing, who do not see the robot, no obstacles: in this seeded layout a person walks toward the robot
// from outside the camera's view within seconds. With the laser the robot tracks them, steps out of the way and
// reaches its goal. (A regression check on one layout; the rates over many runs are in docs/benchmarks.md.)
TEST(ScenarioTest, WithTheLaserTheRobotStepsOutOfTheWayOfSomeoneItCannotSee) {
  ScenarioOptions options;
  options.seed = 1;
  options.pedestrians = 5;
  options.crowd = CrowdKind::kPacing;
  options.laser = true;
  const Layout layout = MakeLayout(options, 2, 1);
  const RunResult with_laser = RunOnce(layout, Policy::kMorpRb, options);
  EXPECT_EQ(ToString(with_laser.outcome), std::string("success")) << with_laser.collided_with;
  EXPECT_GT(with_laser.tracking_ms.size(), 100u);  // it tracked on laser scans

  // Camera only, that person walks into it, never having been in the camera's view: the run says so.
  options.laser = false;
  const RunResult camera_only = RunOnce(layout, Policy::kMorpRb, options);
  EXPECT_EQ(ToString(camera_only.outcome), std::string("collision"));
  EXPECT_EQ(camera_only.collided_with, "person");
  EXPECT_FALSE(camera_only.person_in_view_s.has_value()) << *camera_only.person_in_view_s;
}

// The camera's view by the simulator's truth: its field and range from where it is mounted, walls hiding what is
// behind them.
TEST(ScenarioTest, TheCamerasViewIsItsFieldAndRangeWithNoWallBetween) {
  nav::OccupancyGrid grid(200, 200, 0.05, nav::Pose2{-5.0, -5.0, 0.0}, nav::kFreeCell);
  for (int y = 0; y < 200; ++y) grid.at(nav::CellIndex{140, y}) = nav::kOccupiedCell;  // a wall at x = 2.0 m
  const drivers::sim::SimCameraOptions camera;                                         // 85.2 degrees, 6 m
  const nav::Pose2 robot{-3.0, 0.0, 0.0};
  EXPECT_TRUE(InCameraView(grid, camera, robot, {1.0, 0.0}));    // ahead
  EXPECT_TRUE(InCameraView(grid, camera, robot, {1.0, 3.0}));    // 37 degrees left of the camera
  EXPECT_FALSE(InCameraView(grid, camera, robot, {-1.0, 3.0}));  // 56 degrees left: outside the field
  EXPECT_FALSE(InCameraView(grid, camera, robot, {-4.0, 0.0}));  // behind
  EXPECT_FALSE(InCameraView(grid, camera, robot, {3.0, 0.0}));   // beyond the wall
  const nav::Pose2 turned{-3.0, 0.0, std::numbers::pi / 2.0};
  EXPECT_TRUE(InCameraView(grid, camera, turned, {-3.0, 4.0}));            // ahead once turned left
  EXPECT_FALSE(InCameraView(grid, camera, turned, {1.0, 0.0}));            // now to its right
  EXPECT_FALSE(InCameraView(grid, camera, {-4.5, 0.0, 0.0}, {1.9, 0.0}));  // 6.3 m: beyond its range
}

// The same layout and seed give the same run, step for step: the graph runs in lockstep on the simulator's clock.
TEST(ScenarioTest, ARunThroughTheDaemonsGraphIsTheSameEveryTime) {
  ScenarioOptions options;
  options.seed = 3;
  options.pedestrians = 5;
  options.timeout_s = 15.0;
  const Layout layout = MakeLayout(options, 0, 0);
  const RunResult a = RunOnce(layout, Policy::kMorpRb, options);
  const RunResult b = RunOnce(layout, Policy::kMorpRb, options);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.path_length_m, b.path_length_m);
  EXPECT_EQ(a.depth_ms.size(), b.depth_ms.size());
  EXPECT_GT(a.path_length_m, 1.0);
}

// The paper's crowd: the robot faces its goal; each person starts and ends their walk in the area the robot must
// cross (3 to 7 m before the goal, at least 1.5 m ahead of the robot, within 2.5 m of the straight way), walks it
// once, slowly, and stands at its end.
TEST(ScenarioTest, ThePapersPeopleWalkOnceAcrossTheRobotsWayAndStand) {
  ScenarioOptions options;
  options.pedestrians = 5;
  for (int world = 0; world < 4; ++world) {
    const Layout layout = MakeLayout(options, world, 0);
    SCOPED_TRACE("world " + std::to_string(world));
    const Eigen::Vector2d start = layout.start.translation();
    const Eigen::Vector2d way = layout.goal - start;
    const Eigen::Vector2d along = way.normalized();
    EXPECT_NEAR(layout.start.yaw_rad, std::atan2(way.y(), way.x()), 1e-9);
    EXPECT_EQ(layout.routes.size(), 5u);
    for (const auto& route : layout.routes) {
      for (const Eigen::Vector2d& p : {route.start, route.goal}) {
        const double a = (p - start).dot(along);
        EXPECT_GE(a, std::max(1.5, way.norm() - 7.0) - 1e-9);
        EXPECT_LE(a, way.norm() - 3.0 + 1e-9);
        EXPECT_LE(std::abs((p - start).dot(Eigen::Vector2d(-along.y(), along.x()))), 2.5 + 1e-9);
      }
      EXPECT_GE((route.goal - route.start).norm(), 2.5);
      EXPECT_LE((route.goal - route.start).norm(), 5.0);
    }
    EXPECT_FALSE(layout.crowd.turn_back);
    EXPECT_LE(layout.crowd.max_speed_mps, 0.35);
  }
  options.crowd = CrowdKind::kPacing;
  const Layout pacing = MakeLayout(options, 0, 0);
  EXPECT_TRUE(pacing.crowd.turn_back);
  EXPECT_GT(pacing.crowd.preferred_speed_mps, 0.7);
}

TEST(ScenarioTest, TheSameSeedGivesTheSameScenario) {
  ScenarioOptions options;
  options.pedestrians = 2;
  options.static_obstacles = 2;
  const Layout a = MakeLayout(options, 3, 1);
  const Layout b = MakeLayout(options, 3, 1);
  EXPECT_EQ(a.goal, b.goal);
  EXPECT_EQ(a.start.translation(), b.start.translation());
  ASSERT_EQ(a.routes.size(), 2u);
  ASSERT_EQ(b.routes.size(), 2u);
  EXPECT_EQ(a.routes[0].start, b.routes[0].start);
  const Layout c = MakeLayout(options, 3, 2);
  EXPECT_NE(a.goal, c.goal);
}

}  // namespace
}  // namespace corridor::scenario
