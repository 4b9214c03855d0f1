#include "nav/mission/docking.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace corridor::nav {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// What a depth camera 0.1 m ahead of the robot's centre with a 85 degree view sees (base frame): the dock's face
// (DockGeometry's width, face_distance_m ahead of `dock`) in front of a wall 0.12 m behind it, points every few
// millimetres with noise; nothing nearer the camera than 0.2 m.
std::vector<Eigen::Vector2d> SeeDock(const Pose2& robot, const Pose2& dock, const DockGeometry& geometry,
                                     std::mt19937& rng, double face_width_m = -1.0) {
  if (face_width_m < 0.0) face_width_m = geometry.width_m;
  std::normal_distribution<double> noise(0.0, 0.002);
  const Pose2 base_T_dock = robot.Inverse() * dock;
  std::vector<Eigen::Vector2d> out;
  const auto see = [&](double along, double depth, bool occluded_by_face) {
    const Eigen::Vector2d p = base_T_dock.Transform({geometry.face_distance_m + depth, along});
    const Eigen::Vector2d from_camera = p - Eigen::Vector2d(0.1, 0.0);
    if (from_camera.norm() < 0.2 || std::abs(std::atan2(from_camera.y(), from_camera.x())) > 42.0 * kDeg) return;
    if (occluded_by_face && std::abs(along) < face_width_m / 2.0 + 0.05) return;
    out.push_back(p + from_camera.normalized() * noise(rng));
  };
  for (double a = -face_width_m / 2.0; a <= face_width_m / 2.0; a += 0.004) see(a, 0.0, false);
  for (double a = -1.5; a <= 1.5; a += 0.004) see(a, 0.12, true);
  return out;
}

TEST(DockingTest, TheFaceIsFoundInFrontOfItsWall) {
  const DockingOptions o;
  std::mt19937 rng(3);
  const Pose2 dock{2.0, 1.0, 0.3};
  const Pose2 robot = dock * Pose2{-0.7, 0.03, 2.0 * kDeg};  // near the staging pose
  const auto scan = SeeDock(robot, dock, o.dock, rng);
  // The map puts the dock 8 cm and 5 degrees off where it is.
  const Pose2 expected = robot.Inverse() * (dock * Pose2{0.05, -0.06, 5.0 * kDeg});
  const auto found = FindDockFace(scan, expected, o);
  ASSERT_TRUE(found);
  const Pose2 error = (robot * *found).Inverse() * dock;
  EXPECT_LT(error.translation().norm(), 0.01);
  EXPECT_LT(std::abs(error.yaw_rad), 1.5 * kDeg);
}

TEST(DockingTest, SomethingOfAnotherWidthIsNotTheDock) {
  const DockingOptions o;
  std::mt19937 rng(4);
  const Pose2 dock{0.0, 0.0, 0.0};
  const Pose2 robot = dock * Pose2{-0.7, 0.0, 0.0};
  const Pose2 expected = robot.Inverse() * dock;
  EXPECT_FALSE(FindDockFace(SeeDock(robot, dock, o.dock, rng, 0.25), expected, o));  // a person, a bin
  EXPECT_FALSE(FindDockFace(SeeDock(robot, dock, o.dock, rng, 0.8), expected, o));   // a cabinet
  EXPECT_FALSE(FindDockFace({}, expected, o));
}

// Drives a docking in closed loop with unicycle kinematics at the camera's rate and odometry that drifts by 1 %.
struct DockingRun {
  Pose2 robot;  // truth
  DockingStep last;
};
DockingRun DriveDocking(Docking& docking, Pose2 robot, const Pose2& dock, const DockGeometry& geometry,
                        double seconds) {
  constexpr double kDt = 1.0 / 15.0;
  std::mt19937 rng(7);
  Pose2 odom = robot;  // odometry frame = world frame at the start
  DockingRun run{robot, {}};
  for (int i = 0; i < static_cast<int>(seconds / kDt); ++i) {
    const auto scan = SeeDock(robot, dock, geometry, rng);
    run.last = docking.Update(i * kDt, odom, &scan);
    if (run.last.finished()) break;
    const Pose2 step{run.last.twist.linear_mps * kDt, 0.0, run.last.twist.angular_rps * kDt};
    robot = robot * step;
    odom = odom * Pose2{step.x_m * 1.01, step.y_m * 1.01, step.yaw_rad * 1.01};
  }
  run.robot = robot;
  return run;
}

TEST(DockingTest, DocksWithinACentimetreFromAStagingPoseTheMapGotWrong) {
  const DockingOptions o;
  const Pose2 dock{5.0, -2.0, 1.2};
  // The robot stands 4 cm and 4 degrees off its staging pose, and the map's dock is 6 cm off the real one.
  const Pose2 start = StagingPose(dock, o.dock) * Pose2{0.02, -0.04, -4.0 * kDeg};
  Docking docking = Docking::Dock(o, dock * Pose2{0.0, 0.06, 3.0 * kDeg}, 0.0);
  const DockingRun run = DriveDocking(docking, start, dock, o.dock, 60.0);
  ASSERT_EQ(run.last.phase, DockingPhase::kDocked) << run.last.error;
  const Pose2 error = run.robot.Inverse() * dock;
  EXPECT_LT(error.translation().norm(), 0.01);
  EXPECT_LT(std::abs(error.yaw_rad), 1.0 * kDeg);
  EXPECT_GE(docking.sightings(), o.min_sightings);
}

TEST(DockingTest, ADockThatIsNotThereFailsTheDocking) {
  const DockingOptions o;
  Docking docking = Docking::Dock(o, Pose2{5.0, 0.0, 0.0}, 0.0);
  const std::vector<Eigen::Vector2d> nothing;
  DockingStep step;
  for (double t = 0.0; t < o.not_seen_s + 1.0 && !step.finished(); t += 0.1) {
    step = docking.Update(t, StagingPose({5.0, 0.0, 0.0}, o.dock), &nothing);
    EXPECT_EQ(step.twist.linear_mps, 0.0);
  }
  EXPECT_EQ(step.phase, DockingPhase::kFailed);
  EXPECT_EQ(step.error, "the dock was not seen where the map puts it");
}

TEST(DockingTest, UndockingBacksStraightOffToTheStagingPose) {
  const DockingOptions o;
  const Pose2 docked{1.0, 1.0, std::numbers::pi / 2.0};
  Docking undocking = Docking::Undock(o, docked, 0.0);
  Pose2 robot = docked;
  DockingStep step;
  for (int i = 0; i < 600 && !step.finished(); ++i) {
    step = undocking.Update(i * 0.05, robot, nullptr);
    if (i == 0) {
      EXPECT_LT(step.twist.linear_mps, 0.0);
    }
    robot = robot * Pose2{step.twist.linear_mps * 0.05, 0.0, step.twist.angular_rps * 0.05};
  }
  EXPECT_EQ(step.phase, DockingPhase::kUndocked);
  EXPECT_LT((robot.translation() - StagingPose(docked, o.dock).translation()).norm(), o.undock_tolerance_m);
}

TEST(DockingTest, OptionsAreValidated) {
  DockingOptions o;
  EXPECT_NO_THROW(Validate(o));
  o.blind_distance_m = 0.1;
  EXPECT_THROW(Validate(o), std::invalid_argument);
  o = {};
  o.dock.staging_distance_m = 0.1;
  EXPECT_THROW(Validate(o), std::invalid_argument);
}

TEST(DockingTest, AnIdleRobotLowOnChargeGoesToChargeAndRetriesLater) {
  ChargingPolicy never(ChargingOptions{});
  EXPECT_FALSE(never.ShouldGo(0.0, 0.01, false, false));
  ChargingPolicy policy(ChargingOptions{.charge_below_percent = 20.0, .retry_s = 60.0});
  EXPECT_FALSE(policy.ShouldGo(0.0, 0.25, false, false));  // charged enough
  EXPECT_FALSE(policy.ShouldGo(1.0, 0.15, false, true));   // busy with a mission
  EXPECT_FALSE(policy.ShouldGo(2.0, 0.15, true, false));   // on the charger already
  EXPECT_TRUE(policy.ShouldGo(3.0, 0.15, false, false));
  EXPECT_FALSE(policy.ShouldGo(4.0, 0.15, false, false));  // it set off a second ago
  EXPECT_TRUE(policy.ShouldGo(64.0, 0.14, false, false));  // that did not work out: again
}

// A dock against a room's wall docks from a staging pose in the open; one whose staging pose is near another wall, or
// in a keep-out zone, or off the map, is named with the reason.
TEST(DockingTest, ADockWhoseStagingPoseCannotBeReachedIsNamed) {
  OccupancyGrid room(82, 62, 0.05, Pose2{-0.05, -0.05, 0.0}, kFreeCell);  // 4 x 3 m inside, walled by one cell
  for (int x = 0; x < room.width(); ++x) room.at({x, 0}) = room.at({x, room.height() - 1}) = kOccupiedCell;
  for (int y = 0; y < room.height(); ++y) room.at({0, y}) = room.at({room.width() - 1, y}) = kOccupiedCell;
  const DockGeometry dock;  // staging 0.7 m back
  const Costmap costmap(room, {}, CostmapOptions{});
  EXPECT_EQ(DockUnreachable(costmap, {3.75, 1.5, 0.0}, dock), std::nullopt);  // facing the east wall
  // Facing the north wall 0.12 m from the west wall: the staging pose is as close to it.
  const auto near_wall = DockUnreachable(costmap, {0.12, 2.75, std::numbers::pi / 2.0}, dock);
  ASSERT_TRUE(near_wall);
  EXPECT_NE(near_wall->find("m from an obstacle; the robot needs 0.20 m"), std::string::npos) << *near_wall;
  EXPECT_NE(near_wall->find("(0.12, 2.05)"), std::string::npos) << *near_wall;
  const auto outside = DockUnreachable(costmap, {0.3, 1.5, 0.0}, dock);  // backs out through the west wall
  ASSERT_TRUE(outside);
  EXPECT_NE(outside->find("outside the map"), std::string::npos) << *outside;
  const Zone keep_out{"z", "no-go", ZoneKind::kKeepOut, {{2.5, 1.0}, {3.5, 1.0}, {3.5, 2.0}, {2.5, 2.0}}, 0.0};
  const Costmap zoned(room, std::vector<Zone>{keep_out}, CostmapOptions{});
  const auto zone = DockUnreachable(zoned, {3.75, 1.5, 0.0}, dock);
  ASSERT_TRUE(zone);
  EXPECT_NE(zone->find("keep-out zone"), std::string::npos) << *zone;
}

}  // namespace
}  // namespace corridor::nav
