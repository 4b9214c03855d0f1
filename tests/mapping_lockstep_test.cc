// Mapping a new building through the daemon's graph in simulated time (testing/lockstep_robot.h): graph SLAM from the
// simulated laser while a mission drives the robot round the small house, started and stopped through the API; the
// map saved is the active map, with its 3D map beside it, its walls where the house's reference map has them, and
// localization goes on in it. Exploring two rooms: the robot drives to the frontiers on its own until none is left, and
// the map saved has both rooms with their walls where the world has them. (The mapping requests over real HTTP are
// tests/mapping_test.mjs.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "drivers/sim/world.h"
#include "nav/map/map_io.h"
#include "server/runtime/topics.h"
#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"
#include "testing/temp_dir.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
using testing::SourceDir;
namespace fs = std::filesystem;

// The occupied cells' centres of a map_server map, in the map frame.
std::vector<Eigen::Vector2d> OccupiedCells(const fs::path& yaml) {
  const nav::OccupancyGrid grid = nav::LoadMap(yaml);
  std::vector<Eigen::Vector2d> out;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (grid.at({x, y}) == nav::kOccupiedCell) out.push_back(grid.CellCenter({x, y}));
    }
  }
  return out;
}

// The share of `built`'s cells within two cells (10 cm) of one of `reference`'s, on the reference's lattice.
double ShareOnWalls(const std::vector<Eigen::Vector2d>& built, const std::vector<Eigen::Vector2d>& reference,
                    double resolution_m) {
  const auto key = [resolution_m](const Eigen::Vector2d& p) {
    return std::make_pair(static_cast<long>(std::lround(p.x() / resolution_m)),
                          static_cast<long>(std::lround(p.y() / resolution_m)));
  };
  std::set<std::pair<long, long>> walls;
  for (const Eigen::Vector2d& p : reference) walls.insert(key(p));
  int near = 0;
  for (const Eigen::Vector2d& p : built) {
    const auto [kx, ky] = key(p);
    bool found = false;
    for (long dx = -2; dx <= 2 && !found; ++dx) {
      for (long dy = -2; dy <= 2 && !found; ++dy) found = walls.contains({kx + dx, ky + dy});
    }
    near += found ? 1 : 0;
  }
  return built.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(built.size());
}

TEST(MappingLockstep, AMapBuiltWhileDrivingThroughTheHouseHasItsWallsWhereTheReferenceHasThem) {
  const fs::path house = SourceDir() / "config/worlds/small_house";
  const testing::TempDir dir("corridor_mapping");
  std::ofstream(dir.path() / "corridor.yaml") << "map: {file: \"" << (house / "maps/map.yaml").string()
                                              << "\"}\n"
                                                 "sim:\n"
                                                 "  world: \""
                                              << (house / "worlds/small_house.world").string()
                                              << "\"\n"
                                                 "  start: {x_m: -3.5, y_m: 1.0, yaw_deg: 270}\n"
                                                 "localization: {source: mcl}\n";
  LockstepRobot robot(dir.path() / "corridor.yaml");
  const auto localization = [&] { return robot.Call("GET", "/api/v1/localization").body; };
  const auto mapping = [&] { return robot.Call("GET", "/api/v1/mapping").body; };
  ASSERT_TRUE(robot.StepUntil([&] { return localization()["health"] == "ok"; }, 15.0)) << "localization never ok";

  const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/mapping/start", {{"name", "house-new"}});
  ASSERT_EQ(started.status, 202) << started.body.dump();
  ASSERT_TRUE(robot.StepUntil([&] { return mapping()["active"] == true; }, 5.0)) << "mapping never under way";
  EXPECT_EQ(robot.Call("POST", "/api/v1/mapping/start", {{"name", "other"}}).body["code"], "already_mapping");
  // No map may take the name of the one being made.
  const LockstepRobot::Reply taken =
      robot.Call("POST", "/api/v1/maps", {{"name", "house-new"}, {"yaml", ""}, {"image", ""}});
  EXPECT_EQ(taken.status, 409) << taken.body.dump();
  EXPECT_NE(taken.body.value("detail", "").find("being made"), std::string::npos) << taken.body.dump();
  // Round the middle of the house and back (the planner still plans on the reference map).
  const json waypoints = json::array({{{"x", -3.5}, {"y", -3.3}},
                                      {{"x", 2.0}, {"y", -3.8}},
                                      {{"x", 5.0}, {"y", -1.0}},
                                      {{"x", 2.0}, {"y", 0.3}},
                                      {{"x", -3.0}, {"y", 0.5}}});
  ASSERT_EQ(robot.Call("POST", "/api/v1/missions", {{"waypoints", waypoints}}).status, 201);
  json state;
  robot.StepUntil(
      [&] {
        state = robot.State();
        return state["mission"]["status"] != "active";
      },
      180.0);
  ASSERT_EQ(state["mission"]["status"], "succeeded") << state["mission"].dump();
  json during;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        during = mapping();
        return !during["map"].is_null();
      },
      5.0))
      << "no map as built so far";
  EXPECT_EQ(robot.Call("GET", during["map"]["image_url"].get<std::string>()).status, 200);

  ASSERT_EQ(robot.Call("POST", "/api/v1/mapping/stop", json::object()).status, 202);
  json saved;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        saved = mapping();
        return saved["active"] == false;
      },
      20.0))
      << "the map never saved";
  std::printf("mapped %d scans, %d submaps, %d loop closures\n", saved["scans"].get<int>(), saved["submaps"].get<int>(),
              saved["loop_closures"].get<int>());
  EXPECT_EQ(saved["saved"], "house-new") << saved.dump();
  EXPECT_EQ(robot.Call("GET", "/api/v1/map").body["name"], "house-new");
  // Its 3D map, built from the depth frames meanwhile, is saved beside it.
  EXPECT_TRUE(robot.StepUntil([&] { return fs::exists(robot.state_dir() / "maps/house-new/map.bt"); }, 5.0));
  EXPECT_EQ(robot.Call("GET", "/api/v1/map/octomap").body["map"], "house-new");

  // Its walls lie on the reference map's walls: most occupied cells within 10 cm of one. The reference is itself a
  // robot's SLAM map, a few centimetres off the world in places (localizing in it at the start is 5 cm and 0.7
  // degrees off the simulator's truth).
  const std::vector<Eigen::Vector2d> built = OccupiedCells(robot.state_dir() / "maps/house-new/map.yaml");
  const double on_walls = ShareOnWalls(built, OccupiedCells(house / "maps/map.yaml"), 0.05);
  std::printf("%zu occupied cells, %.1f %% within 10 cm of the reference's walls\n", built.size(), 100.0 * on_walls);
  EXPECT_GT(built.size(), 300u);
  EXPECT_GT(on_walls, 0.8);
  // Localization goes on in the new map, where the robot is.
  ASSERT_TRUE(robot.StepUntil([&] { return localization()["health"] == "ok"; }, 15.0)) << "lost in the new map";
  EXPECT_EQ(localization()["source"], "mcl");
  const json s = robot.State();
  EXPECT_LT(std::hypot(s["pose"]["x"].get<double>() - s["sim_true_pose"]["x"].get<double>(),
                       s["pose"]["y"].get<double>() - s["sim_true_pose"]["y"].get<double>()),
            0.1)
      << s["pose"].dump() << " against the truth " << s["sim_true_pose"].dump();
}

// Two 4 x 4 m rooms side by side, the wall between them open from y 1.5 to 2.5 m.
nav::OccupancyGrid TwoRooms() {
  nav::OccupancyGrid grid = drivers::sim::RoomMap(8.0, 4.0, 0.05);
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d c = grid.CellCenter({x, y});
      if (std::abs(c.x() - 4.0) < 0.075 && (c.y() < 1.5 || c.y() > 2.5)) grid.at({x, y}) = nav::kOccupiedCell;
    }
  }
  return grid;
}

TEST(MappingLockstep, ExploringDrivesToTheFrontiersUntilNoneIsLeftAndSavesBothRooms) {
  const testing::TempDir dir("corridor_rooms");
  nav::SaveMap(TwoRooms(), dir.path() / "rooms.yaml");
  std::ofstream(dir.path() / "corridor.yaml") << "map: {file: rooms.yaml}\n"
                                                 "sim:\n"
                                                 "  world: rooms.yaml\n"
                                                 "  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 180}\n"
                                                 "localization: {source: mcl}\n";
  LockstepRobot robot(dir.path() / "corridor.yaml");
  ASSERT_TRUE(robot.StepUntil([&] { return robot.Call("GET", "/api/v1/localization").body["health"] == "ok"; }, 15.0))
      << "localization never ok";
  EXPECT_EQ(robot.Call("POST", "/api/v1/mapping/explore", json::object()).status, 400) << "a name is needed";
  const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/mapping/explore", {{"name", "rooms-explored"}});
  ASSERT_EQ(started.status, 202) << started.body.dump();
  const auto mapping = [&] { return robot.Call("GET", "/api/v1/mapping").body; };
  ASSERT_TRUE(robot.StepUntil([&] { return mapping()["exploring"] == true; }, 5.0)) << "not exploring";
  int goals = 0;
  std::string last_goal;
  json saved;
  robot.StepUntil(
      [&] {
        const auto mission = robot.graph().bus().Get(server::topics::kMission).latest();
        if (mission && mission->id != last_goal) {
          last_goal = mission->id;
          ++goals;
        }
        saved = mapping();
        return saved["active"] == false;
      },
      300.0);
  ASSERT_EQ(saved["saved"], "rooms-explored") << saved.dump();
  EXPECT_EQ(saved["exploring"], false);
  EXPECT_GE(goals, 2) << "explored without driving to frontiers";
  // Both rooms are in the map, and its walls are the world's.
  const fs::path built = robot.state_dir() / "maps/rooms-explored/map.yaml";
  const nav::OccupancyGrid grid = nav::LoadMap(built);
  for (const auto& [x, y] : {std::pair{1.0, 1.0}, {3.0, 3.0}, {5.0, 1.0}, {7.0, 3.0}, {6.0, 2.0}}) {
    const auto cell = grid.WorldToCell({x, y});
    ASSERT_TRUE(cell) << x << ", " << y << " is off the map";
    EXPECT_EQ(grid.at(*cell), nav::kFreeCell) << x << ", " << y << " is not free in the map";
  }
  // Over the simulator's seeds 1-8 the share is 0.93-1.00 (a turn mapped a cell or two off now and then).
  EXPECT_GT(ShareOnWalls(OccupiedCells(built), OccupiedCells(dir.path() / "rooms.yaml"), 0.05), 0.9);
  EXPECT_EQ(robot.Call("GET", "/api/v1/map").body["name"], "rooms-explored");
}

}  // namespace
}  // namespace corridor
