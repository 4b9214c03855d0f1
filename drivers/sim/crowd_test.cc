#include "drivers/sim/crowd.h"

#include <gtest/gtest.h>

#include <numbers>

#include "drivers/sim/sim_robot.h"

namespace corridor::drivers::sim {
namespace {

World Room(double width_m, double height_m, const std::vector<StaticObstacle>& obstacles = {}) {
  World world = WorldFromMap(RoomMap(width_m, height_m, 0.05), WorldOptions{});
  AddObstacles(world, obstacles);
  return world;
}

// Runs the crowd for `seconds`; returns the smallest distance between any two people's centres. Every person who
// reached their goal (turned back) is counted in `arrived`.
double Walk(Crowd& crowd, double seconds, std::vector<bool>* arrived = nullptr) {
  double closest = std::numeric_limits<double>::infinity();
  if (arrived) arrived->assign(crowd.pedestrians().size(), false);
  for (int step = 0; step < static_cast<int>(seconds * 100); ++step) {
    crowd.Step(0.01);
    const auto& people = crowd.pedestrians();
    for (std::size_t i = 0; i < people.size(); ++i) {
      if (arrived && people[i].returning) (*arrived)[i] = true;
      for (std::size_t j = i + 1; j < people.size(); ++j) {
        closest = std::min(closest, (people[i].position - people[j].position).norm());
      }
    }
  }
  return closest;
}

TEST(CrowdTest, TwoPeopleHeadOnPassEachOtherWithoutTouching) {
  const World world = Room(12, 6);
  Crowd crowd(world, {{{1, 3}, {11, 3}}, {{11, 3}, {1, 3}}}, CrowdOptions{});
  std::vector<bool> arrived;
  const double closest = Walk(crowd, 15.0, &arrived);
  EXPECT_GE(closest, 2 * crowd.options().radius_m - 0.01);
  EXPECT_TRUE(arrived[0]);
  EXPECT_TRUE(arrived[1]);
}

TEST(CrowdTest, FivePeopleCrossingThroughOneCentreKeepApartAndArrive) {
  const World world = Room(12, 12);
  std::vector<PedestrianRoute> routes;
  for (int i = 0; i < 5; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 5;
    const Eigen::Vector2d out(std::cos(a), std::sin(a));
    routes.push_back({Eigen::Vector2d(6, 6) + 4.5 * out, Eigen::Vector2d(6, 6) - 4.5 * out});
  }
  const CrowdOptions options;
  Crowd crowd(world, routes, options);
  std::vector<bool> arrived;
  const double closest = Walk(crowd, 25.0, &arrived);
  EXPECT_GE(closest, 2 * options.radius_m - 0.02);
  for (std::size_t i = 0; i < routes.size(); ++i) EXPECT_TRUE(arrived[i]) << "person " << i;
}

TEST(CrowdTest, PeopleWalkAroundStaticObstaclesAndTurnBackAtTheirGoal) {
  StaticObstacle pillar;
  pillar.center = {6, 2.6};  // the straight line passes 0.4 m from its centre
  pillar.size_m = 0.5;
  const World world = Room(12, 6, {pillar});
  Crowd crowd(world, {{{1, 3}, {11, 3}}}, CrowdOptions{});
  double closest = std::numeric_limits<double>::infinity();
  bool returned = false;
  for (int step = 0; step < 3000; ++step) {
    crowd.Step(0.01);
    const Pedestrian& p = crowd.pedestrians()[0];
    closest = std::min(closest, (p.position - pillar.center).norm());
    returned = returned || p.returning;
  }
  EXPECT_GE(closest, pillar.size_m + crowd.options().radius_m - 0.02);
  EXPECT_TRUE(returned);
}

// The DPoom evaluation's agents: each walks once to its goal and stands there; the others pass them like an obstacle.
TEST(CrowdTest, PeopleWhoDoNotTurnBackStandAtTheirGoalAndAreWalkedRound) {
  const World world = Room(12, 6);
  CrowdOptions options;
  options.turn_back = false;
  options.preferred_speed_mps = 0.35;
  // A stands at (6, 3) after 1.5 m; B, behind A's goal, walks through it to (11, 3) once A is standing.
  Crowd crowd(world, {{{4.5, 3}, {6, 3}}, {{1, 3}, {11, 3}}}, options);
  double closest = std::numeric_limits<double>::infinity();
  for (int step = 0; step < 5000; ++step) {
    crowd.Step(0.01);
    const auto& people = crowd.pedestrians();
    closest = std::min(closest, (people[0].position - people[1].position).norm());
  }
  const auto& people = crowd.pedestrians();
  EXPECT_TRUE(people[0].arrived);
  EXPECT_FALSE(people[0].returning);
  EXPECT_LT((people[0].position - Eigen::Vector2d(6, 3)).norm(), options.goal_tolerance_m + 0.05);
  EXPECT_EQ(people[0].velocity, Eigen::Vector2d::Zero());
  EXPECT_TRUE(people[1].arrived);
  EXPECT_LT((people[1].position - Eigen::Vector2d(11, 3)).norm(), options.goal_tolerance_m + 0.05);
  EXPECT_GE(closest, 2 * options.radius_m - 0.02);
}

TEST(CrowdTest, OrcaKeepsThePreferredVelocityWhenNothingIsNear) {
  const Eigen::Vector2d v =
      OrcaVelocity({0, 0}, {0.5, 0}, 0.25, {0.8, 0}, 1.2, 2.0, 0.01, {{{0, 5}, {0, 0}, 0.25, true}});
  EXPECT_NEAR(v.x(), 0.8, 1e-9);
  EXPECT_NEAR(v.y(), 0.0, 1e-9);
}

TEST(CrowdTest, RandomRoutesAreInFreeSpaceAwayFromTheRobot) {
  const World world = Room(10, 10);
  std::mt19937 rng(3);
  RouteArea area;
  area.center = {5, 5};
  area.within_m = 4.0;
  area.clearance_m = 1.5;
  const auto routes = RandomRoutes(world.collision, 5, 0.25, area, rng);
  ASSERT_EQ(routes.size(), 5u);
  for (const auto& r : routes) {
    EXPECT_GE((r.start - Eigen::Vector2d(5, 5)).norm(), 1.5);
    EXPECT_LE((r.start - Eigen::Vector2d(5, 5)).norm(), 4.0);
    const double length = (r.goal - r.start).norm();
    EXPECT_GE(length, 4.0);
    EXPECT_LE(length, 10.0);
    for (const Eigen::Vector2d& p : {r.start, r.goal}) {
      EXPECT_GT(p.x(), 0.25);
      EXPECT_LT(p.x(), 9.75);
      EXPECT_GT(p.y(), 0.25);
      EXPECT_LT(p.y(), 9.75);
    }
  }
}

TEST(CrowdTest, TheRobotSeesPeopleAndUnmappedObstaclesAndBumpsIntoThem) {
  StaticObstacle box;
  box.shape = StaticObstacle::Shape::kBox;
  box.center = {5, 1.5};
  box.size_m = 0.5;
  auto world = std::make_shared<World>(Room(10, 6, {box}));
  EXPECT_EQ(world->obstacles.size(), 1u);
  SimOptions o;
  o.start = {2.0, 3.0, 0.0};
  o.camera.dropout_fraction = 0.0;
  o.laser.noise_m = 0.0;
  // Someone walking straight at the robot from 4 m ahead.
  o.pedestrians = {{{6.0, 3.0}, {1.0, 3.0}}};
  SimRobot robot(world, o);
  std::shared_ptr<const LaserScan> scan;
  robot.SetScanHandler([&](std::shared_ptr<const LaserScan> s) { scan = std::move(s); });
  std::shared_ptr<const RgbdFrame> frame;
  robot.SetFrameHandler([&](std::shared_ptr<const RgbdFrame> f) { frame = std::move(f); });
  for (int i = 0; i < 11; ++i) robot.Step();
  ASSERT_TRUE(scan);
  ASSERT_TRUE(frame);
  // The laser's forward beam (index 180 of 360 from -pi) meets the person's front: 4 m less their radius, less
  // what they walked (0.1 s at up to 0.8 m/s).
  const double person_x = robot.pedestrians()[0].position.x();
  EXPECT_NEAR(scan->ranges[180], person_x - 0.25 - 2.0, 0.05);
  // The camera sees them too, at the centre of the image.
  const double depth_m = frame->depth_mm.at<std::uint16_t>(frame->depth_mm.rows / 2, frame->depth_mm.cols / 2) * 1e-3;
  EXPECT_GT(depth_m, 0.0);
  EXPECT_LT(depth_m, person_x - 2.0);
  // The box: the beam toward it (at -45 degrees: (5,1.5) from (2,3) is atan2(-1.5, 3) = -26.6 degrees).
  const int beam = 180 + static_cast<int>(std::lround(std::atan2(-1.5, 3.0) * 180.0 / std::numbers::pi));
  EXPECT_LT(scan->ranges[beam], 3.36 - 0.4);
  // They walk into the standing robot: its bumper says so.
  bool bumped = false;
  for (int i = 0; i < 800 && !bumped; ++i) {
    robot.Step();
    bumped = robot.bumper_pressed();
  }
  EXPECT_TRUE(bumped);
  EXPECT_LT((robot.pedestrians()[0].position - robot.true_pose().translation()).norm(), 0.45 + 0.01);
}

TEST(CrowdTest, PeopleWhoSeeTheRobotWalkRoundItAndTheOthersWalkIntoIt) {
  auto world = std::make_shared<World>(Room(10, 6));
  SimOptions o;
  o.start = {2.0, 3.0, 0.0};
  o.pedestrians = {{{6.0, 3.0}, {1.0, 3.0}}};  // straight at the standing robot from 4 m ahead
  for (const bool see : {false, true}) {
    o.crowd.see_robot = see;
    SimRobot robot(world, o);
    bool bumped = false;
    double closest = std::numeric_limits<double>::infinity();
    bool passed = false;
    for (int i = 0; i < 1000 && !bumped && !passed; ++i) {
      robot.Step();
      bumped = robot.bumper_pressed();
      const Eigen::Vector2d person = robot.pedestrians()[0].position;
      closest = std::min(closest, (person - robot.true_pose().translation()).norm());
      passed = person.x() < 1.5;
    }
    EXPECT_EQ(bumped, !see) << "sees the robot: " << see;
    if (see) {
      EXPECT_TRUE(passed);
      EXPECT_GE(closest, 0.45 - 0.02);  // the robot's radius and theirs
    }
  }
}

}  // namespace
}  // namespace corridor::drivers::sim
