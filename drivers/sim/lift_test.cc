#include "drivers/sim/lift.h"

#include <gtest/gtest.h>

#include "drivers/sim/sim_robot.h"

namespace corridor::drivers::sim {
namespace {

// Two 6 x 4 m rooms side by side, 2 m apart: floors A and B. On each a lift car stands against the room's east wall:
// its door spans y 1.3..2.7 at x = 4.3 (world), the car's centre 0.7 m further east.
TEST(SimLiftTest, TheCarCarriesTheRobotToTheOtherFloorAndOpensThere) {
  const Floors floors = FloorsSideBySide({RoomMap(6.0, 4.0, 0.05), RoomMap(6.0, 4.0, 0.05)}, 2.0);
  ASSERT_EQ(floors.offsets.size(), 2u);
  EXPECT_NEAR(floors.offsets[1].x(), 6.1 + 2.0, 0.051);  // the room and its wall cells, then the gap
  EXPECT_EQ(floors.FloorAt({3.0, 2.0}), 0);
  EXPECT_EQ(floors.FloorAt(floors.offsets[1] + Eigen::Vector2d(3.0, 2.0)), 1);
  SimLiftOptions lift;
  lift.id = "east";
  lift.travel_s = 2.0;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d o = floors.offsets[static_cast<std::size_t>(i)];
    lift.stops.push_back({i == 0 ? "A" : "B", o + Eigen::Vector2d(4.3, 1.3), o + Eigen::Vector2d(4.3, 2.7),
                          nav::Pose2{o.x() + 5.0, o.y() + 2.0, 0.0}});
  }
  SimOptions options;
  options.camera.width = 80;
  options.camera.height = 60;
  options.laser.enabled = false;
  options.start = {3.0, 2.0, 0.0};
  options.lifts.push_back(lift);
  const auto world = std::make_shared<const World>(WorldFromMap(floors.map, WorldOptions{}));
  SimRobot robot(world, options);
  const auto drive = [&](double speed, int steps) {
    for (int i = 0; i < steps; ++i) {
      if (i % 10 == 0) robot.SetVelocity({speed, 0.0});
      robot.Step();
    }
    robot.SetVelocity({});
    for (int i = 0; i < 50; ++i) robot.Step();
  };
  // The door is closed: the robot stops at it.
  drive(0.3, 800);
  EXPECT_LT(robot.true_pose().x_m, 4.3 - 0.2);
  EXPECT_FALSE(robot.CallLift("east", "C"));
  EXPECT_FALSE(robot.CallLift("west", "A"));
  ASSERT_TRUE(robot.CallLift("east", "A"));  // already there: the door opens
  robot.Step();
  EXPECT_TRUE(robot.lifts()[0].door_open);
  drive(0.3, 400);
  const nav::Pose2 aboard = robot.true_pose();
  EXPECT_GT(aboard.x_m, 4.5);  // in the car, short of its back wall
  EXPECT_LT(aboard.x_m, 5.7 - 0.2);
  ASSERT_TRUE(robot.CallLift("east", "B"));
  robot.Step();
  for (int i = 0; i < 150; ++i) {
    if (i % 50 == 0) {
      ASSERT_TRUE(robot.CallLift("east", "B"));  // asked again on its way: it keeps going
    }
    robot.Step();
  }
  EXPECT_FALSE(robot.lifts()[0].door_open);
  EXPECT_EQ(robot.lifts()[0].destination, "B");
  for (int i = 0; i < 100; ++i) robot.Step();
  const SimLiftState state = robot.lifts()[0];
  EXPECT_EQ(state.floor, "B");
  EXPECT_TRUE(state.door_open);
  EXPECT_EQ(state.destination, "");
  EXPECT_NEAR(robot.true_pose().x_m, aboard.x_m + floors.offsets[1].x(), 1e-9);
  EXPECT_NEAR(robot.true_pose().y_m, aboard.y_m, 1e-9);
  // Backing out onto floor B.
  drive(-0.3, 400);
  EXPECT_LT(robot.true_pose().x_m, floors.offsets[1].x() + 4.3);
  robot.CallLift("east", "");
  robot.Step();
  EXPECT_FALSE(robot.lifts()[0].door_open);
}

}  // namespace
}  // namespace corridor::drivers::sim
