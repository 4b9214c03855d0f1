#include "nav/localization/monte_carlo.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "nav/localization/graph_slam.h"
#include "nav/localization/scan_history.h"
#include "nav/localization/test_world.h"

namespace corridor::nav {
namespace {

using testworld::Room;
using testworld::ScanAt;
using testworld::Wall;

// The room's map as a robot would have made it: scans from a grid of poses rendered at their true poses.
const OccupancyGrid& RoomMap() {
  static const OccupancyGrid map = [] {
    std::vector<RangeScan> scans;
    std::vector<Pose2> poses;
    for (double x = -3.5; x <= 5.5; x += 1.0) {
      for (double y = -2.5; y <= 3.5; y += 1.0) {
        poses.push_back({x, y, 0.0});
        scans.push_back(ScanAt(Room(), poses.back()));
      }
    }
    std::vector<const RangeScan*> pointers;
    for (const RangeScan& s : scans) pointers.push_back(&s);
    return RenderScans(pointers, poses, 0.05);
  }();
  return map;
}

bool Near(const Pose2& a, const Pose2& b, double metres, double radians) {
  return (a.translation() - b.translation()).norm() <= metres && std::abs(WrapAngle(a.yaw_rad - b.yaw_rad)) <= radians;
}

// A drive around the room's inner wall: straight legs and turns, 5 cm per step.
std::vector<Pose2> Drive() {
  std::vector<Pose2> path{{-2.5, -2.0, 0.0}};
  const auto go = [&](int steps, double forward, double turn) {
    for (int i = 0; i < steps; ++i) path.push_back(path.back() * Pose2{forward, 0.0, turn});
  };
  go(60, 0.05, 0.0);                   // east along the south wall, north of the inner wall's end
  go(20, 0.0, std::numbers::pi / 40);  // turn left
  go(60, 0.05, 0.0);                   // north
  go(20, 0.0, std::numbers::pi / 40);  // west
  go(100, 0.05, 0.0);
  return path;
}

// Odometry along `truth` with 5 % noise on each step and a heading drift, seeded.
std::vector<Pose2> NoisyOdometry(const std::vector<Pose2>& truth, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Pose2> odom{truth.front()};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const Pose2 step = truth[i - 1].Inverse() * truth[i];
    const double length = step.translation().norm();
    odom.push_back(odom.back() * Pose2{step.x_m * (1.03 + 0.05 * normal(random)), step.y_m,
                                       step.yaw_rad * (1.0 + 0.05 * normal(random)) + 0.02 * length});
  }
  return odom;
}

TEST(MonteCarloLocalizationTest, FollowsADriveWithNoisyOdometryWithinCentimetres) {
  const std::vector<Pose2> truth = Drive();
  const std::vector<Pose2> odom = NoisyOdometry(truth, 3);
  MonteCarloLocalization mcl(RoomMap(), MonteCarloOptions{}, 5);
  mcl.SetPose(truth.front(), 0.1, 0.05);
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const LocalizationEstimate& e = mcl.Update(odom[i], ScanAt(Room(), truth[i]));
    if (i > 10) worst = std::max(worst, (e.pose.translation() - truth[i].translation()).norm());
  }
  // Dead reckoning alone ends far off; the filter stays on the map.
  EXPECT_GT((odom.back().translation() - truth.back().translation()).norm(), 0.3);
  EXPECT_LT(worst, 0.05);
  EXPECT_TRUE(Near(mcl.estimate().pose, truth.back(), 0.03, 0.02));
  EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kOk);
}

TEST(MonteCarloLocalizationTest, APersonNotOnTheMapDoesNotDragTheEstimate) {
  const std::vector<Pose2> truth = Drive();
  const std::vector<Pose2> odom = NoisyOdometry(truth, 4);
  MonteCarloLocalization mcl(RoomMap(), MonteCarloOptions{}, 6);
  mcl.SetPose(truth.front(), 0.1, 0.05);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    // Someone walking half a metre ahead of the robot the whole way, and a box by the north wall.
    std::vector<Wall> world = Room();
    const Eigen::Vector2d person = truth[i].Transform({0.6, 0.0});
    world.push_back({person + Eigen::Vector2d(-0.2, -0.2), person + Eigen::Vector2d(0.2, 0.2)});
    world.push_back({{0.0, 3.2}, {1.0, 3.2}});
    mcl.Update(odom[i], ScanAt(world, truth[i]));
  }
  EXPECT_TRUE(Near(mcl.estimate().pose, truth.back(), 0.05, 0.03));
}

TEST(MonteCarloLocalizationTest, RelocalizesAKidnappedRobotFromOneScan) {
  MonteCarloLocalization mcl(RoomMap(), MonteCarloOptions{}, 7);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> x(-3.5, 5.5);
  std::uniform_real_distribution<double> y(-2.5, 3.5);
  std::uniform_real_distribution<double> yaw(-std::numbers::pi, std::numbers::pi);
  int found = 0;
  int tried = 0;
  while (tried < 10) {
    const Pose2 truth{x(random), y(random), yaw(random)};
    if (truth.x_m > 1.2 && truth.x_m < 1.8 && truth.y_m < -0.8) continue;                    // inside the inner wall
    if (truth.x_m > 3.8 && truth.x_m < 4.7 && truth.y_m > 1.8 && truth.y_m < 2.7) continue;  // the pillar
    if (truth.x_m < -2.8 && truth.y_m > 0.8 && truth.y_m < 2.7) continue;                    // the alcove's wall
    ++tried;
    const RangeScan scan = ScanAt(Room(), truth);
    if (!mcl.Relocalize(scan)) continue;
    mcl.Update(Pose2{}, scan);
    found += Near(mcl.estimate().pose, truth, 0.1, 0.05);
  }
  EXPECT_GE(found, 9);
}

TEST(MonteCarloLocalizationTest, ScansThatDoNotFitTheMapMakeItLost) {
  MonteCarloLocalization mcl(RoomMap(), MonteCarloOptions{}, 8);
  const Pose2 start{0.0, 0.0, 0.0};
  mcl.SetPose(start, 0.05, 0.02);
  // Another building: a long corridor 2 m wide.
  const std::vector<Wall> corridor = {{{-20, -1}, {20, -1}}, {{-20, 1}, {20, 1}}};
  Pose2 odom;
  for (int i = 0; i < 20; ++i) {
    odom = odom * Pose2{0.1, 0.0, 0.0};
    mcl.Update(odom, ScanAt(corridor, Pose2{0.1 * i, 0.0, 0.0}));
  }
  EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kLost);
  // Back in the room, relocalization finds it again.
  const Pose2 truth{2.5, 1.0, 0.7};
  ASSERT_TRUE(mcl.Relocalize(ScanAt(Room(), truth)));
  odom = odom * Pose2{0.1, 0.0, 0.0};
  mcl.Update(odom, ScanAt(Room(), truth * Pose2{0.1, 0.0, 0.0}));
  EXPECT_TRUE(Near(mcl.estimate().pose, truth * Pose2{0.1, 0.0, 0.0}, 0.05, 0.03));
  EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kOk);
}

TEST(MonteCarloLocalizationTest, LostUntilFoundHoldsLostThoughTheScansAgreeAgainUntilASearchFindsTheRobot) {
  for (const bool until_found : {false, true}) {
    MonteCarloOptions options;
    options.lost_until_found = until_found;
    MonteCarloLocalization mcl(RoomMap(), options, 8);
    mcl.SetPose(Pose2{0.0, 0.0, 0.0}, 0.05, 0.02);
    const std::vector<Wall> corridor = {{{-20, -1}, {20, -1}}, {{-20, 1}, {20, 1}}};
    Pose2 odom;
    for (int i = 0; i < 20; ++i) {
      odom = odom * Pose2{0.1, 0.0, 0.0};
      mcl.Update(odom, ScanAt(corridor, Pose2{0.1 * i, 0.0, 0.0}));
    }
    ASSERT_EQ(mcl.estimate().health, LocalizationHealth::kLost);
    // The scans fit the map at the estimate again (as a narrow view may at a wrong heading, by chance).
    for (int i = 0; i < 3 * options.lost_after; ++i) {
      odom = odom * Pose2{0.0, 0.0, 0.06};
      mcl.Update(odom, ScanAt(Room(), mcl.estimate().pose * Pose2{0.0, 0.0, 0.06}));
    }
    EXPECT_EQ(mcl.estimate().health, until_found ? LocalizationHealth::kLost : LocalizationHealth::kOk) << until_found;
    // A search that finds it ends being lost.
    const Pose2 truth{2.5, 1.0, 0.7};
    ASSERT_TRUE(mcl.Relocalize(ScanAt(Room(), truth)));
    for (int i = 1; i <= 2; ++i) {
      odom = odom * Pose2{0.1, 0.0, 0.0};
      mcl.Update(odom, ScanAt(Room(), truth * Pose2{0.1 * i, 0.0, 0.0}));
    }
    EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kOk) << until_found;
  }
}

TEST(MonteCarloLocalizationTest, ScansThatOnlyHalfFitMakeItLostWhenAskedTo) {
  // A third of each scan on the map's walls, the rest half a metre beyond them: not lost by lost_agreement (0.2),
  // never ok either. doubtful_after makes that lost too.
  const Pose2 pose{2.0, 1.5, 0.3};
  RangeScan scan = ScanAt(Room(), pose);
  for (std::size_t i = 0; i < scan.hits.size(); ++i) {
    if (i % 3 != 0) scan.hits[i] *= (scan.hits[i].norm() + 0.5f) / scan.hits[i].norm();
  }
  for (const int doubtful_after : {0, 30}) {
    MonteCarloOptions options;
    options.doubtful_after = doubtful_after;
    MonteCarloLocalization mcl(RoomMap(), options, 3);
    mcl.SetPose(pose, 0.02, 0.01);
    for (int i = 0; i < 29; ++i) mcl.Update(Pose2{}, scan);
    EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kUncertain) << doubtful_after;
    EXPECT_GT(mcl.estimate().agreement, options.lost_agreement);
    mcl.Update(Pose2{}, scan);
    EXPECT_EQ(mcl.estimate().health, doubtful_after > 0 ? LocalizationHealth::kLost : LocalizationHealth::kUncertain)
        << doubtful_after;
  }
}

TEST(MonteCarloLocalizationTest, CarriedElsewhereStandingStillItIsLostEvenWhereItsScanHalfFits) {
  // Localized and still, then carried: what it sees now puts a third of the scan on the map's walls at its old pose
  // (above lost_agreement), against nearly all of it before. With lost_drop_ratio that fall is being lost.
  const Pose2 pose{2.0, 1.5, 0.3};
  RangeScan carried = ScanAt(Room(), pose);
  for (std::size_t i = 0; i < carried.hits.size(); ++i) {
    if (i % 3 != 0) carried.hits[i] *= (carried.hits[i].norm() + 0.5f) / carried.hits[i].norm();
  }
  for (const double ratio : {0.0, 0.5}) {
    MonteCarloOptions options;
    options.lost_drop_ratio = ratio;
    MonteCarloLocalization mcl(RoomMap(), options, 4);
    mcl.SetPose(pose, 0.02, 0.01);
    for (int i = 0; i < 20; ++i) mcl.Update(Pose2{}, ScanAt(Room(), pose));
    ASSERT_EQ(mcl.estimate().health, LocalizationHealth::kOk);
    for (int i = 0; i < options.lost_after; ++i) mcl.Update(Pose2{}, carried);
    EXPECT_GT(mcl.estimate().agreement, options.lost_agreement);
    EXPECT_EQ(mcl.estimate().health, ratio > 0.0 ? LocalizationHealth::kLost : LocalizationHealth::kUncertain) << ratio;
    // A new pose starts the usual agreement afresh: that scan is then only doubtful, as in a cluttered room.
    mcl.SetPose(pose, 0.02, 0.01);
    for (int i = 0; i < 2 * options.lost_after; ++i) mcl.Update(Pose2{}, carried);
    EXPECT_EQ(mcl.estimate().health, LocalizationHealth::kUncertain) << ratio;
  }
}

// What the depth camera's scan gives: 85 degrees ahead, out to 4 m.
RangeScan CameraScanAt(const std::vector<Wall>& walls, const Pose2& pose) {
  RangeScan scan = ScanAt(walls, pose, 85, 85.0 * std::numbers::pi / 180.0);
  std::erase_if(scan.hits, [](const Eigen::Vector2f& p) { return p.norm() > 4.0f; });
  return scan;
}

TEST(MonteCarloLocalizationTest, FollowsADriveFromTheCamerasNarrowScan) {
  const std::vector<Pose2> truth = Drive();
  const std::vector<Pose2> odom = NoisyOdometry(truth, 3);
  MonteCarloOptions options;
  options.max_range_m = 4.0;
  MonteCarloLocalization mcl(RoomMap(), options, 5);
  mcl.SetPose(truth.front(), 0.1, 0.05);
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const LocalizationEstimate& e = mcl.Update(odom[i], CameraScanAt(Room(), truth[i]));
    if (i > 10) worst = std::max(worst, (e.pose.translation() - truth[i].translation()).norm());
  }
  EXPECT_GT((odom.back().translation() - truth.back().translation()).norm(), 0.3);
  EXPECT_LT(worst, 0.1);
  // Looking along the last leg at one wall and a corner, the view holds the robot less well sideways than a laser's.
  EXPECT_TRUE(Near(mcl.estimate().pose, truth.back(), 0.08, 0.06));
  EXPECT_NE(mcl.estimate().health, LocalizationHealth::kLost);
}

TEST(MonteCarloLocalizationTest, RelocalizesFromTheCameraScansOfOneTurnJoinedByOdometry) {
  // From random poses the robot turns on the spot until its history has seen enough of the room (as the daemon's
  // localization asks, PlanNarrowViewSearch); the history joins the turn's narrow scans by the (noisy) odometry into
  // one view of the room, which the search finds.
  MonteCarloOptions options;
  options.max_range_m = 4.0;
  MonteCarloLocalization mcl(RoomMap(), options, 7);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(-3.0, 5.0);
  std::uniform_real_distribution<double> y(-2.0, 3.0);
  std::uniform_real_distribution<double> yaw(-std::numbers::pi, std::numbers::pi);
  std::normal_distribution<double> normal(0.0, 1.0);
  int found = 0;
  int tried = 0;
  while (tried < 10) {
    const Pose2 start{x(random), y(random), yaw(random)};
    if (start.x_m > 1.0 && start.x_m < 2.0 && start.y_m < -0.6) continue;                    // at the inner wall
    if (start.x_m > 3.6 && start.x_m < 4.9 && start.y_m > 1.6 && start.y_m < 2.9) continue;  // the pillar
    if (start.x_m < -2.6 && start.y_m > 0.6 && start.y_m < 2.9) continue;                    // the alcove's wall
    ++tried;
    ScanHistory history;
    Pose2 truth = start;
    Pose2 odom;
    history.Add(odom, CameraScanAt(Room(), truth));
    int steps = 0;
    while (!PlanNarrowViewSearch(history, odom).search) {  // 9 degrees a step, 1 % scale error and noise
      ASSERT_GT(PlanNarrowViewSearch(history, odom).turn_rps, 0.0);
      ASSERT_LE(++steps, 41) << "more than a turn";
      truth = truth * Pose2{0.0, 0.0, std::numbers::pi / 20.0};
      odom = odom * Pose2{0.0, 0.0, std::numbers::pi / 20.0 * (1.01 + 0.01 * normal(random))};
      history.Add(odom, CameraScanAt(Room(), truth));
    }
    if (!mcl.Relocalize(history.Merged(odom))) continue;
    found += Near(mcl.estimate().pose, truth, 0.1, 0.05);
  }
  EXPECT_GE(found, 9);
}

TEST(ScanHistoryTest, KeepsScansAsTheRobotMovesAndJoinsThemInTheRobotsFrame) {
  ScanHistoryOptions options;
  options.max_travel_m = 1.0;
  ScanHistory history(options);
  RangeScan ahead;
  ahead.hits = {Eigen::Vector2f(2.0f, 0.0f)};
  history.Add(Pose2{}, ahead);
  history.Add(Pose2{0.01, 0.0, 0.0}, ahead);  // barely moved: not kept
  EXPECT_EQ(history.size(), 1u);
  // Half a metre on and turned left a quarter: the first scan's point (2, 0) in the odometry frame is, from here,
  // 1.5 m to the right.
  history.Add(Pose2{0.5, 0.0, std::numbers::pi / 2.0}, RangeScan{});
  const RangeScan merged = history.Merged(Pose2{0.5, 0.0, std::numbers::pi / 2.0});
  ASSERT_EQ(merged.hits.size(), 1u);
  EXPECT_NEAR(merged.hits[0].x(), 0.0, 1e-5);
  EXPECT_NEAR(merged.hits[0].y(), -1.5, 1e-5);
  EXPECT_NEAR(history.CoveredAngle(Pose2{0.5, 0.0, std::numbers::pi / 2.0}), 2.0 * std::numbers::pi / 36.0, 1e-9);
  // Beyond the travel kept, the oldest goes; Clear forgets everything.
  history.Add(Pose2{1.2, 0.0, 0.0}, RangeScan{});
  EXPECT_EQ(history.size(), 2u);
  EXPECT_TRUE(history.Merged(Pose2{1.2, 0.0, 0.0}).hits.empty());
  history.Clear();
  EXPECT_EQ(history.size(), 0u);
}

TEST(MonteCarloLocalizationTest, RejectsAnEmptyMap) {
  EXPECT_THROW(MonteCarloLocalization(OccupancyGrid(0, 0, 0.05, Pose2{}), MonteCarloOptions{}, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
