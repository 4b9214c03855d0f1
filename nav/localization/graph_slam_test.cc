#include "nav/localization/graph_slam.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "nav/localization/carmen_log.h"
#include "nav/localization/pose_graph.h"
#include "nav/localization/test_world.h"
#include "nav/localization/trajectory_error.h"
#include "testing/source_dir.h"

namespace corridor::nav {
namespace {

using testworld::Room;
using testworld::ScanAt;

// A square loop of side 4 m walked in 40 steps, each measured with a bias; the last node comes back to the first.
TEST(PoseGraphTest, ALoopClosureSpreadsTheDriftOverTheLoop) {
  PoseGraph graph;
  std::vector<Pose2> truth{Pose2{}};
  for (int i = 1; i <= 40; ++i)
    truth.push_back(truth.back() * Pose2{0.4, 0.0, i % 10 == 0 ? std::numbers::pi / 2 : 0.0});
  Pose2 dead_reckoning;
  graph.AddNode(dead_reckoning);
  for (int i = 1; i <= 40; ++i) {
    Pose2 step = truth[i - 1].Inverse() * truth[i];
    step.yaw_rad += 0.01;  // a heading drift
    dead_reckoning = dead_reckoning * step;
    graph.AddNode(dead_reckoning);
    graph.AddConstraint({i - 1, i, step, 1.0, 1.0, false});
  }
  const double drift = (dead_reckoning.translation() - truth.back().translation()).norm();
  // Node 40 is where node 0 was (the loop's truth), seen by a scan match.
  graph.AddConstraint({0, 40, truth[0].Inverse() * truth[40], 10.0, 10.0, true});
  graph.Optimize();
  EXPECT_GT(drift, 0.5);
  EXPECT_LT((graph.pose(40).translation() - truth.back().translation()).norm(), 0.05);
  double worst = 0.0;
  for (int i = 0; i <= 40; ++i) worst = std::max(worst, (graph.pose(i).translation() - truth[i].translation()).norm());
  EXPECT_LT(worst, 0.25);  // the error left is spread along the loop, not piled at its end
  EXPECT_THROW(graph.AddConstraint({0, 41, Pose2{}, 1.0, 1.0, false}), std::out_of_range);
}

TEST(TrajectoryErrorTest, RelativeErrorsIgnoreWhereTheEstimateIsAnchored) {
  std::vector<Pose2> truth;
  for (int i = 0; i < 50; ++i) truth.push_back({0.1 * i, 0.0, 0.0});
  // The same trajectory in another frame is perfect by relative error, and off by absolute error.
  std::vector<Pose2> moved;
  for (const Pose2& p : truth) moved.push_back(Pose2{3.0, -2.0, 1.0} * p);
  EXPECT_NEAR(LocalRelativeError(truth, moved).translation_m.max, 0.0, 1e-9);
  EXPECT_GT(AbsoluteError(truth, moved).translation_m.mean, 1.0);
  // A 1 cm step error at step 10 shows in every local pair across it, and only in those.
  std::vector<Pose2> bumped = truth;
  for (int i = 10; i < 50; ++i) bumped[i].x_m += 0.01;
  const RelativeError local = LocalRelativeError(truth, bumped, 0.5);
  EXPECT_NEAR(local.translation_m.max, 0.01, 1e-9);
  EXPECT_GT(local.translation_m.count, 150);
  EXPECT_THROW(LocalRelativeError(truth, std::vector<Pose2>(3)), std::invalid_argument);
}

// Odometry along `truth` read 3 % long and drifting 3 degrees per metre.
std::vector<Pose2> BiasedOdometry(const std::vector<Pose2>& truth) {
  std::vector<Pose2> odom{truth.front()};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Pose2 step = truth[i - 1].Inverse() * truth[i];
    const double length = step.translation().norm();
    step.x_m *= 1.03;
    step.y_m *= 1.03;
    step.yaw_rad += 0.05 * length;
    odom.push_back(odom.back() * step);
  }
  return odom;
}

TEST(GraphSlamTest, MapsTheRoomTwiceAroundAndComesBackToItsStart) {
  // Twice around the room's inner wall and pillar, 10 cm steps.
  std::vector<Pose2> truth{{-2.5, -2.0, 0.0}};
  const auto go = [&](int steps, double forward, double turn) {
    for (int i = 0; i < steps; ++i) truth.push_back(truth.back() * Pose2{forward, 0.0, turn});
  };
  for (int lap = 0; lap < 2; ++lap) {
    go(70, 0.1, 0.0);
    go(10, 0.0, std::numbers::pi / 20);
    go(50, 0.1, 0.0);
    go(10, 0.0, std::numbers::pi / 20);
    go(70, 0.1, 0.0);
    go(10, 0.0, std::numbers::pi / 20);
    go(50, 0.1, 0.0);
    go(10, 0.0, std::numbers::pi / 20);
  }
  // The loop above is 7 x 5 m; keep it inside the room, clear of the walls.
  for (Pose2& p : truth) p = Pose2{-1.0, -0.5, 0.0} * Pose2{-2.5, -2.0, 0.0}.Inverse() * p;
  const std::vector<Pose2> odom = BiasedOdometry(truth);
  // Started at its true pose (as in an older map of the room), the map is in the room's frame.
  GraphSlam slam(GraphSlamOptions{}, truth.front());
  for (std::size_t i = 0; i < truth.size(); ++i) slam.AddScan(ScanAt(Room(), truth[i]), odom[i]);
  slam.Finish();
  const std::vector<Pose2> estimate = slam.Trajectory();
  ASSERT_EQ(estimate.size(), truth.size());
  const RelativeError revisit = RevisitRelativeError(truth, estimate, 0.5, 10.0);
  const RelativeError odom_revisit = RevisitRelativeError(truth, odom, 0.5, 10.0);
  ASSERT_GT(revisit.translation_m.count, 100);
  EXPECT_GT(odom_revisit.translation_m.mean, 1.0);
  EXPECT_LT(revisit.translation_m.mean, 0.05);  // the target on real logs
  EXPECT_LT(LocalRelativeError(truth, estimate).translation_m.mean, 0.03);
  EXPECT_GT(slam.stats().loop_closures, 0);
  // The map has the room's walls where they are.
  EXPECT_LT((estimate.front().translation() - truth.front().translation()).norm(), 0.1);
  const OccupancyGrid map = slam.RenderMap(0.05);
  int on_wall = 0;
  int checked = 0;
  for (double x = -3.5; x <= 5.5; x += 0.5) {
    const std::optional<CellIndex> c = map.WorldToCell({x, 4.0});
    if (!c) continue;
    ++checked;
    for (int dy = -1; dy <= 1; ++dy) {
      const CellIndex n{c->x, c->y + dy};
      if (map.Contains(n) && map.at(n) == kOccupiedCell) {
        ++on_wall;
        break;
      }
    }
  }
  EXPECT_GT(checked, 10);
  EXPECT_GE(on_wall, checked - 1);
}

TEST(CarmenLogTest, ReadsFlaserLinesAndNamesTheLineOfABadOne) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "corridor_carmen_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path good = dir / "good.log";
  std::ofstream(good) << "# a comment\nODOM 0 0 0 0 0 0 1.0 host 1.0\n"
                      << "FLASER 4 1.0 2.0 3.0 4.0 0.5 -0.5 0.1 0.5 -0.5 0.1 12.5 host 12.5\n";
  const CarmenLog log = ReadCarmenLog(good);
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].ranges_m.size(), 4u);
  EXPECT_DOUBLE_EQ(log.scans[0].pose.x_m, 0.5);
  EXPECT_DOUBLE_EQ(log.scans[0].timestamp_s, 12.5);
  EXPECT_NEAR(log.scans[0].angle_increment_rad, std::numbers::pi / 4, 1e-12);
  const std::filesystem::path bad = dir / "bad.log";
  std::ofstream(bad) << "ODOM 0 0 0\nFLASER 4 1.0 2.0\n";
  try {
    ReadCarmenLog(bad);
    FAIL() << "a short FLASER line was read";
  } catch (const CarmenLogError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.log:2: FLASER has fewer readings than its count 4"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ReadCarmenLog(dir / "missing.log"), CarmenLogError);
  std::filesystem::remove_all(dir);
}

// The Intel Research Lab log (Radish; GPL packaging, so read where it lies, not copied into the tree): its first
// 200 scans, about 90 m with a loop, with biased odometry made from the corrected poses.
TEST(GraphSlamTest, OnTheIntelLogsFirstLoopStaysWithinTheTargets) {
  const std::filesystem::path log_path = testing::SourceDir() / "../shared/data/laser_logs/intel-corrected.log.gz";
  if (!std::filesystem::exists(log_path)) GTEST_SKIP() << log_path << " is not on this machine";
  CarmenLog log = ReadCarmenLog(log_path);
  log.scans.resize(200);
  std::vector<Pose2> truth;
  for (const CarmenScan& s : log.scans) truth.push_back(s.pose);
  const std::vector<Pose2> odom = BiasedOdometry(truth);
  GraphSlam slam;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const CarmenScan& s = log.scans[i];
    slam.AddScan(ScanFromRanges(Pose2{}, s.angle_min_rad, s.angle_increment_rad, s.ranges_m, RangeLimits{}), odom[i]);
  }
  slam.Finish();
  const std::vector<Pose2> estimate = slam.Trajectory();
  const RelativeError local = LocalRelativeError(truth, estimate);
  const RelativeError revisit = RevisitRelativeError(truth, estimate);
  EXPECT_GT(RevisitRelativeError(truth, odom).translation_m.mean, 0.5);
  ASSERT_GT(revisit.translation_m.count, 0);
  EXPECT_LT(local.translation_m.mean, 0.03);
  EXPECT_LT(local.rotation_deg.mean, 0.6);
  EXPECT_LT(revisit.translation_m.mean, 0.05);
}

}  // namespace
}  // namespace corridor::nav
