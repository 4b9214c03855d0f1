#include "drivers/sim/dock.h"

#include <gtest/gtest.h>

#include "drivers/sim/sim_robot.h"

namespace corridor::drivers::sim {
namespace {

// A 6 x 4 m room with a dock whose docked pose is at (3, 2), facing +x.
struct DockRoom {
  SimOptions options;
  std::shared_ptr<const World> world;
};
DockRoom MakeRoom() {
  DockRoom room;
  room.options.camera.width = 80;
  room.options.camera.height = 60;
  room.options.laser.enabled = false;
  room.options.dock = SimDockOptions{};
  room.options.dock->pose = {3.0, 2.0, 0.0};
  room.options.battery.initial_percent = 50.0;
  room.options.battery.capacity_wh = 1.0;
  World w = WorldFromMap(RoomMap(6.0, 4.0, 0.05), WorldOptions{});
  AddDock(w, SimDock(*room.options.dock));
  room.world = std::make_shared<const World>(std::move(w));
  return room;
}

TEST(SimDockTest, TheBlockIsExactAndTheContactsNeedTheDockedPose) {
  SimDockOptions o;
  o.pose = {1.0, 0.0, 0.0};
  const SimDock dock(o);
  const nav::DockGeometry g;
  EXPECT_NEAR(dock.block().Distance({1.0, 0.0}), g.face_distance_m, 1e-12);
  EXPECT_EQ(dock.block().Distance({1.0 + g.face_distance_m + 0.05, 0.1}), 0.0);
  EXPECT_TRUE(dock.Contacts({1.02, 0.0, 0.05}));
  EXPECT_FALSE(dock.Contacts({1.05, 0.0, 0.0}));
  EXPECT_FALSE(dock.Contacts({1.0, 0.0, 0.2}));
}

TEST(SimDockTest, TheRobotStopsAgainstTheDockAndChargesOnIt) {
  DockRoom room = MakeRoom();
  room.options.start = {2.5, 2.0, 0.0};
  SimRobot robot(room.world, room.options);
  std::vector<BatteryState> states;
  robot.SetBatteryHandler([&](const BatteryState& s) { states.push_back(s); });
  int dock_pixels = 0;
  robot.SetFrameHandler([&](std::shared_ptr<const RgbdFrame> f) {
    // The face, 0.71 m from the robot's centre at the start, straight ahead in the middle of the image.
    const std::uint16_t mm = f->depth_mm.at<std::uint16_t>(f->depth_mm.rows / 2, f->depth_mm.cols / 2);
    if (mm > 500 && mm < 700) ++dock_pixels;
  });
  robot.SetVelocity({0.0, 0.0});
  for (int i = 0; i < 100; ++i) robot.Step();
  EXPECT_GT(dock_pixels, 5);
  EXPECT_FALSE(robot.battery_state().on_charger);
  const double drained = robot.battery_state().charge;
  EXPECT_LT(drained, 0.5);
  // Driven at the dock, it stops with its front against the face, on the contacts, and charges.
  for (int i = 0; i < 1500; ++i) {
    if (i % 10 == 0) robot.SetVelocity({0.1, 0.0});
    robot.Step();
  }
  const nav::Pose2 pose = robot.true_pose();
  EXPECT_LE(pose.x_m, 3.0 + 0.01 + 1e-9);  // the face is 1 cm beyond the footprint at the docked pose
  EXPECT_GT(pose.x_m, 2.99);
  EXPECT_TRUE(robot.bumper_pressed());
  const BatteryState s = robot.battery_state();
  EXPECT_TRUE(s.on_charger);
  EXPECT_TRUE(s.charging);
  EXPECT_GT(s.charge, drained);
  ASSERT_FALSE(states.empty());
  EXPECT_TRUE(states.back().on_charger);
  EXPECT_NEAR(static_cast<double>(states.size()), 16.0, 1.0);  // once a second
}

}  // namespace
}  // namespace corridor::drivers::sim
