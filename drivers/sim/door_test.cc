#include "drivers/sim/door.h"

#include <gtest/gtest.h>

#include "drivers/sim/sim_robot.h"

namespace corridor::drivers::sim {
namespace {

// A 6 x 4 m room with a closed door across it at x = 3.
TEST(SimDoorTest, AClosedDoorIsSeenAndStopsTheRobotAndOpenItIsGone) {
  SimOptions options;
  options.camera.width = 80;
  options.camera.height = 60;
  options.laser.enabled = false;
  options.start = {2.0, 2.0, 0.0};
  options.doors.push_back({"d1", {3.0, 0.0}, {3.0, 4.0}});
  const auto world = std::make_shared<const World>(WorldFromMap(RoomMap(6.0, 4.0, 0.05), WorldOptions{}));
  SimRobot robot(world, options);
  std::uint16_t ahead_mm = 0;
  robot.SetFrameHandler([&](std::shared_ptr<const RgbdFrame> f) {
    ahead_mm = f->depth_mm.at<std::uint16_t>(f->depth_mm.rows / 2, f->depth_mm.cols / 2);
  });
  robot.SetVelocity({0.0, 0.0});
  for (int i = 0; i < 20; ++i) robot.Step();
  // The panel, 0.9 m from the camera (10 cm ahead of the centre, the panel's near side at 2.97 m): seen.
  EXPECT_GT(ahead_mm, 800);
  EXPECT_LT(ahead_mm, 1000);
  for (int i = 0; i < 600; ++i) {
    if (i % 10 == 0) robot.SetVelocity({0.3, 0.0});
    robot.Step();
  }
  EXPECT_LT(robot.true_pose().x_m, 3.0 - 0.2);  // its front against the panel
  EXPECT_TRUE(robot.bumper_pressed());
  EXPECT_FALSE(robot.SetDoorOpen("nope", true));
  ASSERT_TRUE(robot.SetDoorOpen("d1", true));
  EXPECT_EQ(robot.doors(), (std::vector<std::pair<std::string, bool>>{{"d1", true}}));
  for (int i = 0; i < 300; ++i) {
    if (i % 10 == 0) robot.SetVelocity({0.3, 0.0});
    robot.Step();
  }
  EXPECT_GT(robot.true_pose().x_m, 3.3);  // through
  EXPECT_GT(ahead_mm, 1500);              // the far wall now
}

}  // namespace
}  // namespace corridor::drivers::sim
