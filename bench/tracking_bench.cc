// Moving-object tracking per laser scan (nav/tracking/moving_objects.h) and one evasion decision
// (nav/policy/evasion.h), on scans the simulator casts in a 12 m room with five people walking. Baseline in the same
// process: BM_PartitionClusters clusters the same ten-scan window with OpenCV's cv::partition (every pair compared),
// the library alternative to the tracker's grid clustering (docs/design.md says why the grid is written here).
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "drivers/sim/sim_robot.h"
#include "nav/policy/evasion.h"
#include "nav/tracking/moving_objects.h"

namespace corridor {
namespace {

struct Recording {
  std::shared_ptr<const nav::OccupancyGrid> map;
  std::vector<double> stamps;
  std::vector<Eigen::Vector2d> sensors;
  std::vector<std::vector<Eigen::Vector2d>> scans;  // world frame
};

// 20 s of 10 Hz scans from a robot standing in the middle of a 12 x 12 m room while five people walk about.
const Recording& Record() {
  static const Recording recording = [] {
    Recording r;
    const nav::OccupancyGrid room = drivers::sim::RoomMap(12.0, 12.0, 0.05);
    r.map = std::make_shared<const nav::OccupancyGrid>(room);
    auto world =
        std::make_shared<const drivers::sim::World>(drivers::sim::WorldFromMap(room, drivers::sim::WorldOptions{}));
    drivers::sim::SimOptions options;
    options.start = {6.0, 6.0, 0.0};
    std::mt19937 rng(4);
    drivers::sim::RouteArea area;
    area.center = {6.0, 6.0};
    area.clearance_m = 1.5;
    options.pedestrians = drivers::sim::RandomRoutes(world->collision, 5, 0.25, area, rng);
    drivers::sim::SimRobot robot(world, options);
    robot.SetScanHandler([&](std::shared_ptr<const drivers::LaserScan> scan) {
      const nav::Pose2 laser = robot.true_pose() * robot.base_T_laser();
      r.stamps.push_back(drivers::ToSeconds(scan->stamp_ns));
      r.sensors.push_back(laser.translation());
      r.scans.push_back(nav::ScanToWorld(laser, scan->angle_min_rad, scan->angle_increment_rad, scan->range_min_m,
                                         scan->range_max_m, scan->ranges));
    });
    while (r.scans.size() < 200) robot.Step();
    return r;
  }();
  return recording;
}

void BM_TrackerUpdate(benchmark::State& state) {
  const Recording& r = Record();
  nav::MovingObjectTracker tracker{nav::MovingObjectOptions{}};
  tracker.SetMap(r.map);
  std::size_t i = 0;
  double offset = 0.0;  // replays run on in time, so that the window is never reset
  for (auto _ : state) {
    tracker.Update(r.stamps[i] + offset, r.sensors[i], r.scans[i]);
    if (++i == r.scans.size()) {
      i = 0;
      offset += r.stamps.back() - r.stamps.front() + 0.1;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_TrackerUpdate)->Unit(benchmark::kMicrosecond);

// The same window's off-map points (ten scans), clustered by cv::partition with the same distance in (x, y, t).
void BM_PartitionClusters(benchmark::State& state) {
  const Recording& r = Record();
  const nav::MovingObjectOptions o;
  std::vector<cv::Point3d> points;
  for (std::size_t k = 100; k < 110; ++k) {
    for (const Eigen::Vector2d& p : r.scans[k]) {
      const auto cell = r.map->WorldToCell(p);
      bool on_map = !cell;
      for (int dy = -2; dy <= 2 && !on_map; ++dy) {
        for (int dx = -2; dx <= 2 && !on_map; ++dx) {
          const nav::CellIndex c{cell->x + dx, cell->y + dy};
          on_map = r.map->Contains(c) && r.map->at(c) >= nav::kOccupiedCell;
        }
      }
      if (!on_map) points.emplace_back(p.x(), p.y(), r.stamps[k] * o.time_scale_mps);
    }
  }
  const double d2 = o.cluster_distance_m * o.cluster_distance_m;
  std::vector<int> labels;
  for (auto _ : state) {
    const int n = cv::partition(points, labels, [d2](const cv::Point3d& a, const cv::Point3d& b) {
      const cv::Point3d d = a - b;
      return d.dot(d) < d2;
    });
    benchmark::DoNotOptimize(n);
  }
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_PartitionClusters)->Unit(benchmark::kMicrosecond);

// One decision when a person is about to walk into the robot: every two-part manoeuvre is predicted against five
// people and checked against the walls within reach.
void BM_EvasionConflict(benchmark::State& state) {
  nav::EvasionOptions options;
  nav::Evasion evasion(options);
  const nav::Pose2 robot{6.0, 6.0, 0.0};
  std::vector<nav::TrackedObject> people;
  for (int i = 0; i < 5; ++i) {
    nav::TrackedObject o;
    o.position = Eigen::Vector2d(8.0 - 0.5 * i, 6.0 + 0.8 * (i - 2));
    o.velocity = (robot.translation() - o.position).normalized() * 0.8;
    o.radius_m = 0.2;
    o.moving = true;
    people.push_back(o);
  }
  std::vector<Eigen::Vector2d> walls;
  for (double y = 4.0; y <= 8.0; y += 0.05) walls.emplace_back(4.5, y);
  for (auto _ : state) {
    benchmark::DoNotOptimize(evasion.Check(robot, {0.26, 0.0}, {9.0, 6.0}, people, walls, nullptr));
  }
}
BENCHMARK(BM_EvasionConflict)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor

BENCHMARK_MAIN();
