#include "nav/planner/planner.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>
#include <queue>
#include <random>

#include "nav/map/map_io.h"

namespace corridor::nav {
namespace {

using testing::SourceDir;

const OccupancyGrid& Map(const std::string& relative) {
  static std::map<std::string, OccupancyGrid> cache;
  auto it = cache.find(relative);
  if (it == cache.end()) it = cache.emplace(relative, LoadMap(SourceDir() / relative)).first;
  return it->second;
}

constexpr const char* kWillow = "config/worlds/willow_garage/willow-full-0.05.yaml";
constexpr const char* kAvz = "tests/data/maps/avz/avz.yaml";
constexpr const char* kDepot = "tests/data/maps/depot/depot.yaml";
constexpr const char* kArena = "tests/data/maps/lse_arena/lse_arena.yaml";
constexpr const char* kHouse = "config/worlds/small_house/maps/map.yaml";

// Where a robot would be parked or sent near `p`: the most open cell within 3 m.
Eigen::Vector2d Open(const Costmap& c, const Eigen::Vector2d& p) {
  const auto cell = MostOpenCell(c, p, 3.0);
  EXPECT_TRUE(cell) << "no traversable cell near " << p.transpose();
  return cell.value_or(p);
}

void ExpectValid(const Costmap& c, const Plan& plan) {
  ASSERT_GE(plan.dense.size(), 2u);
  for (std::size_t i = 1; i + 1 < plan.dense.size(); ++i) {
    const auto cell = c.grid().WorldToCell(plan.dense[i]);
    ASSERT_TRUE(cell);
    EXPECT_TRUE(c.Traversable(c.Index(*cell)));
    EXPECT_LE((plan.dense[i] - plan.dense[i - 1]).norm(), c.grid().resolution_m() * 1.5 + 1e-9);
  }
  for (std::size_t k = 1; k < plan.waypoints.size(); ++k) {
    EXPECT_TRUE(SegmentTraversable(c, plan.waypoints[k - 1].pose.translation(), plan.waypoints[k].pose.translation()));
  }
  EXPECT_GE(plan.min_clearance_m, c.options().robot_radius_m);
}

// Reference: Dijkstra over the same graph and step costs as AStar.
double DijkstraCost(const Costmap& c, CellIndex s, CellIndex g) {
  const int w = c.width();
  std::vector<double> d(c.grid().cells().size(), 1e18);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  const int si = static_cast<int>(c.Index(s));
  d[si] = 0.0;
  q.push({0.0, si});
  const int dx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  const int dy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!q.empty()) {
    const auto [dist, i] = q.top();
    q.pop();
    if (dist > d[i]) continue;
    for (int k = 0; k < 8; ++k) {
      const CellIndex n{i % w + dx[k], i / w + dy[k]};
      if (!c.grid().Contains(n) || !c.Traversable(c.Index(n))) continue;
      if (k >= 4 && (!c.Traversable(c.Index({n.x, i / w})) || !c.Traversable(c.Index({i % w, n.y})))) continue;
      const double step = (k >= 4 ? std::sqrt(2.0) : 1.0) * c.grid().resolution_m() * c.step_factor(c.Index(n));
      if (dist + step < d[c.Index(n)]) {
        d[c.Index(n)] = dist + step;
        q.push({dist + step, static_cast<int>(c.Index(n))});
      }
    }
  }
  return d[c.Index(g)];
}

TEST(PlannerTest, RandomQueriesOnRealMapsGiveValidOptimalPaths) {
  std::mt19937 rng(2022);
  for (const char* name : {kArena, kDepot, kHouse, kAvz}) {
    SCOPED_TRACE(name);
    const OccupancyGrid& g = Map(name);
    const Costmap c(g, {}, CostmapOptions{});
    std::vector<CellIndex> free;
    for (int y = 0; y < g.height(); ++y) {
      for (int x = 0; x < g.width(); ++x) {
        if (c.Traversable(c.Index({x, y}))) free.push_back({x, y});
      }
    }
    ASSERT_FALSE(free.empty());
    std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
    int found = 0;
    for (int trial = 0; trial < 6; ++trial) {
      const CellIndex s = free[pick(rng)];
      const CellIndex t = free[pick(rng)];
      const PlanResult r = PlanPath(c, g.CellCenter(s), g.CellCenter(t));
      const double reference = DijkstraCost(c, s, t);
      if (!r.ok()) {
        EXPECT_EQ(r.error, PlanError::kNoPath);
        EXPECT_GE(reference, 1e17) << "Dijkstra found a path A* missed";
        continue;
      }
      ++found;
      ExpectValid(c, r.plan);
      SearchResult raw = AStar(c, g.CellCenter(s), g.CellCenter(t));
      EXPECT_NEAR(raw.path.cost, reference, 1e-3 * reference + 1e-6) << "A* must be optimal";
    }
    EXPECT_GT(found, 0);
  }
}

TEST(PlannerTest, DistanceCostKeepsClearanceForLittleExtraLengthOnWillowGarage) {
  const OccupancyGrid& g = Map(kWillow);
  CostmapOptions plain_options;
  plain_options.distance_weight = 0.0;
  const Costmap plain(g, {}, plain_options);
  const Costmap modified(g, {}, CostmapOptions{});
  // Across the building (the queries of bench/planner_bench).
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> queries = {{{24.4, 24.1}, {50.0, 12.0}},
                                                                            {{8.0, 10.0}, {45.0, 38.0}},
                                                                            {{33.0, 40.0}, {15.0, 5.0}},
                                                                            {{12.0, 35.0}, {52.0, 30.0}},
                                                                            {{40.0, 8.0}, {10.0, 42.0}}};
  for (const auto& [a, b] : queries) {
    const Eigen::Vector2d s = Open(modified, a);
    const Eigen::Vector2d t = Open(modified, b);
    const PlanResult p = PlanPath(plain, s, t);
    const PlanResult m = PlanPath(modified, s, t);
    ASSERT_TRUE(p.ok()) << p.detail;
    ASSERT_TRUE(m.ok()) << m.detail;
    ExpectValid(modified, m.plan);
    // Measured: 0.36-0.40 m against 0.25 m, for 3-10 % more length.
    EXPECT_GT(m.plan.min_clearance_m, p.plan.min_clearance_m + 0.08);
    EXPECT_GT(m.plan.mean_clearance_m, p.plan.mean_clearance_m + 0.1);
    EXPECT_LE(m.plan.length_m, 1.1 * p.plan.length_m);
  }
}

TEST(PlannerTest, BadGoalsAndStartsGiveTypedErrors) {
  const OccupancyGrid& g = Map(kAvz);
  const Costmap c(g, {}, CostmapOptions{});
  Eigen::Vector2d start;
  for (std::size_t i = 0; i < g.cells().size(); ++i) {
    if (c.Traversable(i) && c.clearance_m(i) > 0.5) {
      start = g.CellCenter({static_cast<int>(i) % g.width(), static_cast<int>(i) / g.width()});
      break;
    }
  }
  CellIndex wall{-1, -1};
  CellIndex unknown{-1, -1};
  for (int i = 0; i < static_cast<int>(g.cells().size()); ++i) {
    const CellIndex cell{i % g.width(), i / g.width()};
    if (g.cells()[i] == kOccupiedCell && wall.x < 0) wall = cell;
    if (g.cells()[i] == kUnknownCell && unknown.x < 0) unknown = cell;
  }
  EXPECT_EQ(PlanPath(c, start, g.CellCenter(wall)).error, PlanError::kGoalOccupied);
  EXPECT_EQ(PlanPath(c, start, g.CellCenter(unknown)).error, PlanError::kGoalOccupied);
  EXPECT_EQ(PlanPath(c, start, {-5.0, 3.0}).error, PlanError::kGoalOutsideMap);
  EXPECT_EQ(PlanPath(c, {1000.0, 3.0}, start).error, PlanError::kStartOutsideMap);
  EXPECT_EQ(PlanPath(c, g.CellCenter(wall), start).error, PlanError::kStartOccupied);
  // Unknown space may be allowed by policy.
  CostmapOptions open;
  open.unknown = UnknownPolicy::kFree;
  const Costmap lenient(g, {}, open);
  EXPECT_NE(PlanPath(lenient, start, g.CellCenter(unknown)).error, PlanError::kGoalOccupied);
}

TEST(PlannerTest, KeepOutZoneAcrossTheOnlyCorridorMeansNoPath) {
  // A corridor 1.5 m wide and 8 m long between two rooms: the only way through.
  OccupancyGrid g(200, 100, 0.05, {}, kOccupiedCell);
  auto clear = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) g.at({x, y}) = kFreeCell;
  };
  clear(5, 5, 50, 95);     // west room
  clear(150, 5, 195, 95);  // east room
  clear(50, 35, 150, 65);  // the corridor
  const Eigen::Vector2d west{1.0, 2.5};
  const Eigen::Vector2d east{9.0, 2.5};
  ASSERT_TRUE(PlanPath(Costmap(g, {}, CostmapOptions{}), west, east).ok());
  Zone zone{"z1", "wet floor", ZoneKind::kKeepOut, {{4.8, 1.0}, {5.2, 1.0}, {5.2, 4.0}, {4.8, 4.0}}, 0.0};
  const std::vector<Zone> zones = {zone};
  const Costmap blocked(g, zones, CostmapOptions{});
  const PlanResult r = PlanPath(blocked, west, east);
  EXPECT_EQ(r.error, PlanError::kNoPath);
  EXPECT_NE(r.detail.find("no path"), std::string::npos);
  EXPECT_EQ(PlanPath(blocked, west, {5.0, 2.5}).error, PlanError::kGoalOccupied);
  EXPECT_NE(PlanPath(blocked, west, {5.0, 2.5}).detail.find("keep-out"), std::string::npos);
}

TEST(PlannerTest, AnObstacleLayersCellsBlockPlansButAreNotTheMapsWalls) {
  // A free room with a wall along y = 0 and, from the obstacle layer, a post at (2.0, 1.0).
  OccupancyGrid g(80, 40, 0.05, {}, kFreeCell);
  for (int x = 0; x < 80; ++x) g.at({x, 0}) = kOccupiedCell;
  std::vector<std::int8_t> layer(g.cells().size(), kFreeCell);
  layer[static_cast<std::size_t>(20) * 80 + 40] = kOccupiedCell;
  const Costmap c(g, layer, {}, CostmapOptions{});
  const Eigen::Vector2d post = g.CellCenter({40, 20});
  EXPECT_FALSE(c.Traversable(c.Index({40, 20})));
  EXPECT_TRUE(c.WallWithin(post, 0.05));
  EXPECT_FALSE(c.WallWithin(post, 0.05, /*mapped_only=*/true));
  EXPECT_TRUE(c.WallWithin(g.CellCenter({40, 0}), 0.05, /*mapped_only=*/true));
  // The same layer cell over a wall of the map is still the map's.
  layer[40] = kOccupiedCell;
  EXPECT_TRUE(Costmap(g, layer, {}, CostmapOptions{}).WallWithin(g.CellCenter({40, 0}), 0.05, true));
}

TEST(PlannerTest, PlansKeepTheGuardsMarginFromTheObstacleLayerWhereThereIsAnotherWay) {
  // A 6 x 4 m room split at x = 3 m by a wall of the map up to y = 2.5 m; the camera saw a post at y = 3.05-3.1 m:
  // a gap of 0.55 m below it (narrower than the robot with the map's margin and the guard's) and 0.85 m above it.
  OccupancyGrid g(120, 80, 0.05, {}, kFreeCell);
  for (int x = 0; x < 120; ++x) g.at({x, 79}) = kOccupiedCell;
  for (int y = 0; y < 50; ++y) g.at({60, y}) = kOccupiedCell;
  std::vector<std::int8_t> layer(g.cells().size(), kFreeCell);
  layer[static_cast<std::size_t>(61) * 120 + 60] = kOccupiedCell;
  const Eigen::Vector2d post = g.CellCenter({60, 61});
  const auto crossing = [&](const Costmap& c) {
    const PlanResult r = PlanPath(c, {1.0, 1.0}, {5.0, 1.0});
    EXPECT_TRUE(r.ok()) << r.detail;
    double y = 0.0;
    for (const Eigen::Vector2d& p : r.plan.dense) {
      if (std::abs(p.x() - post.x()) < 0.03) y = p.y();
    }
    return y;
  };
  EXPECT_GT(crossing(Costmap(g, layer, {}, CostmapOptions{})), post.y() + 0.35);  // above the post
  EXPECT_LT(crossing(Costmap(g, layer, {}, CostmapOptions{.layer_cost = 0.0})), post.y());
  // With the way above closed, the narrow gap is still planned.
  for (int y = 62; y < 80; ++y) g.at({60, y}) = kOccupiedCell;
  EXPECT_LT(crossing(Costmap(g, layer, {}, CostmapOptions{})), post.y());
}

TEST(PlannerTest, SpeedZonesAreCarriedOntoTheWaypoints) {
  OccupancyGrid g(200, 60, 0.05, {}, kFreeCell);
  const std::vector<Zone> zones = {
      Zone{"s", "lobby", ZoneKind::kSpeedLimit, {{4.0, -1.0}, {6.0, -1.0}, {6.0, 4.0}, {4.0, 4.0}}, 0.2}};
  const Costmap c(g, zones, CostmapOptions{});
  const PlanResult r = PlanPath(c, {1.0, 1.5}, {9.0, 1.5}, 0.5);
  ASSERT_TRUE(r.ok());
  double lowest = Costmap::kNoSpeedLimit;
  for (const Waypoint& w : r.plan.waypoints) lowest = std::min(lowest, w.speed_limit_mps);
  EXPECT_NEAR(lowest, 0.2, 1e-6);
  EXPECT_NEAR(r.plan.waypoints.back().pose.yaw_rad, 0.5, 1e-9);
  EXPECT_NEAR(r.plan.length_m, 8.0, 0.1);
}

TEST(PlannerTest, StartTooCloseToAWallCanStillLeave) {
  OccupancyGrid g(100, 100, 0.05, {}, kFreeCell);
  for (int y = 0; y < 100; ++y) g.at({50, y}) = kOccupiedCell;  // a wall at x = 2.5
  const Costmap c(g, {}, CostmapOptions{});
  const PlanResult r = PlanPath(c, {2.38, 2.5}, {0.5, 2.5});  // start 0.12 m from the wall, inside inflation
  ASSERT_TRUE(r.ok()) << r.detail;
  EXPECT_LT(r.plan.waypoints.back().pose.x_m, 0.6);
}

TEST(PlannerTest, ARobotInATightSpotAmongAMapsSpecksCanPlanItsWayOut) {
  // Where a robot drove (avoiding what its camera saw) near the default world's start: inside the inflated band of
  // the map's specks, at a spot from which clearance falls in every direction before it rises, and the goal beyond a
  // line of specks and wall cells whose gaps (a cell wide, beside a wall cell) no robot fits through. Leaving along
  // rising clearance alone finds no way; the robot standing there crosses the band and the unknown specks near it,
  // clear of the walls.
  const OccupancyGrid& g = Map(kWillow);
  const Costmap c(g, {}, CostmapOptions{});
  PathOptions stood;
  stood.robot_at_start = true;
  for (const Eigen::Vector2d& start : {Eigen::Vector2d(24.25, 25.3), Eigen::Vector2d(23.85, 25.77)}) {
    ASSERT_FALSE(c.Traversable(c.Index(*g.WorldToCell(start))));
    EXPECT_EQ(PlanPath(c, start, {24.4, 26.5}).error, PlanError::kNoPath) << "through a gap beside a wall cell";
    const PlanResult r = PlanPath(c, start, {24.4, 26.5}, std::nullopt, nullptr, stood);
    ASSERT_TRUE(r.ok()) << r.detail;
    // Only the way out crosses the band, near the start and clear of the walls.
    for (const Eigen::Vector2d& p : r.plan.dense) {
      if (c.Traversable(c.Index(*g.WorldToCell(p))) || (p - start).norm() <= c.options().robot_radius_m) continue;
      EXPECT_LE((p - start).norm(), kEscapeReachM) << p.transpose();
      EXPECT_FALSE(c.WallWithin(p, c.options().robot_radius_m + g.resolution_m())) << p.transpose();
    }
  }
}

TEST(PlannerTest, ARobotOnAnIslandAmongAMapsSpecksCrossesThemClearOfTheWallsAtACrawl) {
  // Where the robot stood after driving by hand in the default world (issue 36): free floor ringed by the inflation of
  // unknown specks and a few wall cells, the gap between two of those walls 0.45 m across, for a robot 0.4 m wide.
  const OccupancyGrid& g = Map(kWillow);
  const Costmap c(g, {}, CostmapOptions{});
  const Eigen::Vector2d start{24.0, 25.5};
  PathOptions stood;
  stood.robot_at_start = true;
  const PlanResult r = PlanPath(c, start, {18.0, 26.0}, std::nullopt, nullptr, stood);
  ASSERT_TRUE(r.ok()) << r.detail;
  bool over_unknown = false;
  std::size_t last_crawl = 0;
  for (std::size_t i = 0; i < r.plan.dense.size(); ++i) {
    const Eigen::Vector2d& p = r.plan.dense[i];
    const std::size_t cell = c.Index(*g.WorldToCell(p));
    // A cell more than the robot's radius from every wall the map knows, where it crosses the band and the specks.
    if (!c.Traversable(cell)) {
      EXPECT_FALSE(c.WallWithin(p, c.options().robot_radius_m + g.resolution_m())) << p.transpose();
      over_unknown |= c.IsObstacle(cell);
      last_crawl = i;
    }
  }
  EXPECT_TRUE(over_unknown) << "the way out known to the map is a cell narrower than that";
  // It crawls from where it stands until it is across, and not beyond.
  const Eigen::Vector2d across = r.plan.dense[last_crawl];
  for (const Waypoint& w : r.plan.waypoints) {
    const double along = (w.pose.translation() - start).norm();
    if (along < 0.3) {
      EXPECT_LE(w.speed_limit_mps, kBandSpeedMps + 1e-9) << w.pose.x_m << ", " << w.pose.y_m;
    }
  }
  EXPECT_GT(r.plan.waypoints.back().speed_limit_mps, kBandSpeedMps) << "crawling beyond " << across.transpose();
}

TEST(PlannerTest, WhatIsUnderTheRobotIsPassableWhenItPlansFromWhereItStands) {
  // Where a mission's robot stood in the default world after swerving across a band of the map's unknown (grey)
  // cells, which the simulated building does not have: its centre on an unknown cell, free floor 5 cm east.
  const OccupancyGrid& g = Map(kWillow);
  const Costmap c(g, {}, CostmapOptions{});
  const Eigen::Vector2d robot{23.7, 26.28};
  ASSERT_TRUE(c.IsObstacle(c.Index(*g.WorldToCell(robot))));
  EXPECT_EQ(PlanPath(c, robot, {24.4, 26.5}).error, PlanError::kStartOccupied);  // a start given, not stood on
  PathOptions stood;
  stood.robot_at_start = true;
  const PlanResult r = PlanPath(c, robot, {24.4, 26.5}, std::nullopt, nullptr, stood);
  ASSERT_TRUE(r.ok()) << r.detail;
  EXPECT_LT(r.plan.length_m, 1.5);  // out to the east and on: not round the building
  // Obstacle cells only under the footprint.
  for (const Eigen::Vector2d& p : r.plan.dense) {
    if (c.IsObstacle(c.Index(*g.WorldToCell(p)))) {
      EXPECT_LE((p - robot).norm(), c.options().robot_radius_m);
    }
  }
  // Deep in a wall, the footprint reaches no free cell: still no way.
  OccupancyGrid walled(50, 40, 0.05, {}, kOccupiedCell);
  for (int y = 0; y < 40; ++y) {
    for (int x = 28; x < 50; ++x) walled.at({x, y}) = kFreeCell;  // free east of x = 1.4 m
  }
  const Costmap solid(walled, {}, CostmapOptions{});
  EXPECT_EQ(PlanPath(solid, {0.5, 1.0}, {2.0, 1.0}, std::nullopt, nullptr, stood).error, PlanError::kNoPath);
  // A keep-out zone is never left that way.
  OccupancyGrid open(60, 60, 0.05, {}, kFreeCell);
  const std::vector<Zone> zones = {
      Zone{"z", "fence", ZoneKind::kKeepOut, {{1.0, 1.0}, {2.0, 1.0}, {2.0, 2.0}, {1.0, 2.0}}}};
  const Costmap fenced(open, zones, CostmapOptions{});
  EXPECT_EQ(PlanPath(fenced, {1.5, 1.5}, {0.5, 0.5}, std::nullopt, nullptr, stood).error, PlanError::kStartOccupied);
}

TEST(PlannerTest, PointsCostingExtraAreGoneRoundWhereThereIsRoomAndThroughWhereThereIsNot) {
  // 5 m x 3 m of open floor; something the map does not show stands on the straight way across it.
  OccupancyGrid open(100, 60, 0.05, {}, kFreeCell);
  const Costmap c(open, {}, CostmapOptions{});
  const std::vector<Eigen::Vector2d> seen = {{2.5, 1.5}, {2.5, 1.6}, {2.5, 1.4}, {99.0, 99.0}};  // the last off the map
  PathOptions options;
  std::vector<float> extra;
  AddPointCost(c, seen, 0.4, 20.0f, extra);
  ASSERT_EQ(extra.size(), c.grid().cells().size());
  EXPECT_FLOAT_EQ(extra[c.Index(*open.WorldToCell({2.5, 1.5}))], 20.0f);  // once, though near three points
  EXPECT_FLOAT_EQ(extra[c.Index(*open.WorldToCell({2.5, 2.2}))], 0.0f);
  options.extra_cost = extra;
  const PlanResult straight = PlanPath(c, {0.5, 1.5}, {4.5, 1.5});
  const PlanResult round = PlanPath(c, {0.5, 1.5}, {4.5, 1.5}, std::nullopt, nullptr, options);
  ASSERT_TRUE(straight.ok() && round.ok());
  const auto farthest = [](const Plan& plan) {
    double d = 0.0;
    for (const Eigen::Vector2d& p : plan.dense) d = std::max(d, std::abs(p.y() - 1.5));
    return d;
  };
  EXPECT_LT(farthest(straight.plan), 0.05);
  EXPECT_GT(farthest(round.plan), 0.5);  // round the 0.4 m and the points' own 0.1 m
  for (const Eigen::Vector2d& p : round.plan.dense) EXPECT_GT((p - Eigen::Vector2d{2.5, 1.5}).norm(), 0.4);
  // In a corridor 0.9 m wide there is no way round: the path still goes through.
  OccupancyGrid corridor(100, 60, 0.05, {}, kOccupiedCell);
  for (int y = 21; y < 39; ++y) {
    for (int x = 0; x < 100; ++x) corridor.at({x, y}) = kFreeCell;
  }
  const Costmap narrow(corridor, {}, CostmapOptions{});
  std::vector<float> narrow_extra;
  AddPointCost(narrow, seen, 0.4, 20.0f, narrow_extra);
  PathOptions through;
  through.extra_cost = narrow_extra;
  EXPECT_TRUE(PlanPath(narrow, {0.5, 1.5}, {4.5, 1.5}, std::nullopt, nullptr, through).ok());
  // Bad arguments.
  std::vector<float> wrong(10, 0.0f);
  EXPECT_THROW(AddPointCost(c, seen, 0.4, 20.0f, wrong), std::invalid_argument);
  std::vector<float> none;
  EXPECT_THROW(AddPointCost(c, seen, 0.4, -1.0f, none), std::invalid_argument);
}

TEST(PlannerTest, ExtraCostsAddWhereBlockedToWherePeopleWalkAndIgnoreAnotherMapsTraffic) {
  OccupancyGrid open(100, 60, 0.05, {}, kFreeCell);
  const Costmap c(open, {}, CostmapOptions{});
  const std::size_t cells = c.grid().cells().size();
  std::vector<float> traffic(cells, 0.0f);
  const std::size_t walked = c.Index(*open.WorldToCell({2.5, 1.5}));
  const std::size_t aside = c.Index(*open.WorldToCell({4.0, 0.5}));
  traffic[walked] = 3.0f;
  traffic[aside] = 3.0f;
  const std::vector<Eigen::Vector2d> blocking = {{2.5, 1.5}};
  EXPECT_TRUE(ExtraCosts(c, {}, {}, 0.4, 20.0f).empty());
  const std::vector<float> both = ExtraCosts(c, traffic, blocking, 0.4, 20.0f);
  ASSERT_EQ(both.size(), cells);
  EXPECT_FLOAT_EQ(both[walked], 23.0f);
  EXPECT_FLOAT_EQ(both[aside], 3.0f);
  EXPECT_EQ(ExtraCosts(c, traffic, {}, 0.4, 20.0f), traffic);
  // Traffic made over another map (another size) is not this map's: only the blocking points count.
  const std::vector<float> stale(10, 5.0f);
  const std::vector<float> blocked = ExtraCosts(c, stale, blocking, 0.4, 20.0f);
  EXPECT_FLOAT_EQ(blocked[walked], 20.0f);
  EXPECT_FLOAT_EQ(blocked[aside], 0.0f);
}

TEST(PlannerTest, TheRestOfAPathStandsUntilAnObstacleIsDrawnAcrossItAhead) {
  OccupancyGrid open(100, 60, 0.05, {}, kFreeCell);
  const PlanResult plan = PlanPath(Costmap(open, {}, CostmapOptions{}), {0.5, 1.5}, {4.5, 1.5});
  ASSERT_TRUE(plan.ok());
  // A wall across the way at x = 1.5 m.
  OccupancyGrid walled = open;
  for (int y = 0; y < 60; ++y) walled.at({30, y}) = kOccupiedCell;
  const Costmap now(walled, {}, CostmapOptions{});
  EXPECT_TRUE(RestOfPathTraversable(Costmap(open, {}, CostmapOptions{}), plan.plan.waypoints, {0.5, 1.5}));
  EXPECT_FALSE(RestOfPathTraversable(now, plan.plan.waypoints, {0.5, 1.5}));
}

TEST(PlannerTest, CancelStopsALongSearch) {
  const OccupancyGrid& g = Map(kWillow);
  const Costmap c(g, {}, CostmapOptions{});
  const std::atomic<bool> cancel{true};
  const PlanResult r = PlanPath(c, Open(c, {8.0, 10.0}), Open(c, {45.0, 38.0}), std::nullopt, &cancel);
  EXPECT_EQ(r.error, PlanError::kCancelled);
}

}  // namespace
}  // namespace corridor::nav
