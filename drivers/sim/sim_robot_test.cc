#include "drivers/sim/sim_robot.h"

#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>

#include "nav/map/log_odds_grid.h"
#include "nav/map/map_io.h"

namespace corridor::drivers::sim {
namespace {

std::shared_ptr<const World> Arena() {
  return std::make_shared<const World>(
      LoadWorld(testing::SourceDir() / "tests/data/maps/lse_arena/lse_arena.yaml", WorldOptions{}));
}

TEST(SimRobotTest, LockstepDeliversEverySensorAtItsRateInSimulatedTime) {
  SimOptions o;
  o.start = {1.0, 0.75, 0.0};
  o.camera.width = 64;
  o.camera.height = 48;
  SimRobot robot(Arena(), o);
  int frames = 0;
  int odometry = 0;
  int scans = 0;
  TimeNs last_frame_ns = -1;
  robot.SetFrameHandler([&](std::shared_ptr<const RgbdFrame> f) {
    ++frames;
    EXPECT_EQ(f->depth_mm.cols, 64);
    EXPECT_GT(f->stamp_ns, last_frame_ns);
    last_frame_ns = f->stamp_ns;
  });
  robot.SetOdometryHandler([&](const WheelOdometry&) { ++odometry; });
  robot.SetScanHandler([&](std::shared_ptr<const LaserScan> s) {
    ++scans;
    EXPECT_EQ(s->ranges.size(), 360u);
  });
  // Ten simulated seconds, stepped as fast as this machine goes.
  const int steps = static_cast<int>(10.0 * o.physics_rate_hz);
  for (int i = 0; i < steps; ++i) robot.Step();
  EXPECT_EQ(robot.now_ns(), 10 * kNsPerSecond);
  EXPECT_NEAR(frames, 10.0 * o.camera.rate_hz, 1.0);
  EXPECT_NEAR(odometry, 10.0 * o.odometry_rate_hz, 1.0);
  EXPECT_NEAR(scans, 10.0 * o.laser.rate_hz, 1.0);
}

TEST(SimRobotTest, SameSeedSameRun) {
  auto run = [](std::uint32_t seed) {
    SimOptions o;
    o.start = {1.0, 0.75, 0.0};
    o.seed = seed;
    o.camera.width = 32;
    o.camera.height = 24;
    SimRobot robot(Arena(), o);
    WheelOdometry last;
    robot.SetOdometryHandler([&](const WheelOdometry& w) { last = w; });
    for (int i = 0; i < 300; ++i) {
      if (i % 10 == 0) robot.SetVelocity({0.3, 0.4});
      robot.Step();
    }
    return std::pair{robot.true_pose(), last.odom_T_base};
  };
  const auto [truth_a, odom_a] = run(7);
  const auto [truth_b, odom_b] = run(7);
  const auto [truth_c, odom_c] = run(8);
  EXPECT_EQ(truth_a.x_m, truth_b.x_m);
  EXPECT_EQ(odom_a.x_m, odom_b.x_m);
  EXPECT_EQ(truth_a.x_m, truth_c.x_m);  // motion itself is deterministic
  EXPECT_NE(odom_a.x_m, odom_c.x_m);    // the odometry noise follows the seed
  EXPECT_GT(truth_a.x_m, 1.3);          // and the commands were obeyed
}

// A beam cast on its own reads what the whole scan reads at its angle (clockwise from forward is the scan's negative
// angle), from where the robot is at the moment of the cast, not at its last scan.
TEST(SimRobotTest, ALaserBeamCastAloneIsTheScansBeamFromWhereTheRobotIsNow) {
  SimOptions o;
  o.start = {1.0, 0.75, 0.0};
  o.camera.rate_hz = 1.0;
  o.camera.width = 32;
  o.camera.height = 24;
  const auto world = Arena();
  SimRobot robot(world, o);
  std::shared_ptr<const LaserScan> last;
  robot.SetScanHandler([&](std::shared_ptr<const LaserScan> scan) { last = std::move(scan); });
  robot.SetVelocity({0.3, 0.8});
  for (int i = 0; i < 55; ++i) robot.Step();  // half a step's worth past the last scan: the robot has moved since
  ASSERT_TRUE(last);
  const std::shared_ptr<const LaserScan> then = last;
  // Where the robot is now, scanned whole for reference.
  LaserScan now;
  Eigen::Isometry3d world_T_laser = robot.true_pose().ToIsometry3();
  world_T_laser.translation().z() = o.laser.mount_height_m;
  std::mt19937 rng(3);
  CastScan(RayCaster(world->mesh), world_T_laser, o.laser, rng, now);
  int beams = 0;
  int off_then = 0;
  for (std::size_t i = 0; i < now.ranges.size(); ++i) {
    const double a = now.angle_min_rad + static_cast<double>(i) * now.angle_increment_rad;
    const float r = robot.CastLaserBeam(-a);
    if (!std::isfinite(now.ranges[i])) continue;
    ++beams;
    EXPECT_NEAR(r, now.ranges[i], 8.0 * o.laser.noise_m) << a;
    off_then += std::abs(r - then->ranges[i]) > 8.0 * o.laser.noise_m;
  }
  EXPECT_GT(beams, 300);
  EXPECT_GT(off_then, 20);  // the scan before is another view: the beams are not read from it
}

}  // namespace
}  // namespace corridor::drivers::sim

namespace corridor::drivers::sim {
namespace {

TEST(SimRobotTest, LaserScansIntegratedInALogOddsGridRebuildTheArena) {
  const auto world = Arena();
  SimOptions o;
  o.start = {1.0, 0.75, 0.0};
  o.camera.rate_hz = 1.0;
  o.camera.width = 32;
  o.camera.height = 24;
  SimRobot robot(world, o);
  const nav::OccupancyGrid& truth = world->collision;
  nav::LogOddsGrid built(truth.width(), truth.height(), truth.resolution_m(), truth.origin());
  robot.SetScanHandler([&](std::shared_ptr<const LaserScan> scan) {
    const nav::Pose2 pose = robot.true_pose();
    for (std::size_t i = 0; i < scan->ranges.size(); ++i) {
      const double a = scan->angle_min_rad + static_cast<double>(i) * scan->angle_increment_rad;
      const bool hit = std::isfinite(scan->ranges[i]);
      const double r = hit ? scan->ranges[i] : scan->range_max_m;
      built.IntegrateRay(pose.translation(), pose.Transform({r * std::cos(a), r * std::sin(a)}), hit);
    }
  });
  for (int i = 0; i < 200; ++i) robot.Step();  // two seconds standing still: 20 scans
  const nav::OccupancyGrid m = built.ToOccupancyGrid();
  int occupied = 0;
  int on_walls = 0;
  int free = 0;
  int free_on_walls = 0;
  for (int y = 0; y < m.height(); ++y) {
    for (int x = 0; x < m.width(); ++x) {
      // A wall cell or its neighbour: the laser's noise is about a fifth of a cell.
      bool near_wall = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          near_wall |= truth.Contains({x + dx, y + dy}) && truth.at({x + dx, y + dy}) == nav::kOccupiedCell;
      if (m.at({x, y}) == nav::kOccupiedCell) {
        ++occupied;
        on_walls += near_wall;
      } else if (m.at({x, y}) == nav::kFreeCell) {
        ++free;
        free_on_walls += truth.at({x, y}) == nav::kOccupiedCell;
      }
    }
  }
  EXPECT_GT(occupied, 100);
  EXPECT_GE(on_walls, occupied * 98 / 100);
  EXPECT_GT(free, 1000);
  EXPECT_LE(free_on_walls, free / 100);
}

}  // namespace
}  // namespace corridor::drivers::sim
