#include "server/nodes/localization_node.h"

#include <gtest/gtest.h>

#include <thread>

#include "server/nodes/odometry_frame.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

drivers::WheelOdometry Reading(drivers::TimeNs stamp_ns, double x_m, double yaw_rad) {
  drivers::WheelOdometry o;
  o.stamp_ns = stamp_ns;
  o.odom_T_base = nav::Pose2{x_m, 0.0, yaw_rad};
  return o;
}

TEST(OdometryFrameTest, InterpolatesBetweenReadingsAndKeepsTheLastSecond) {
  OdometryFrame frame(nav::Pose2{1.0, 2.0, 0.0});
  EXPECT_FALSE(frame.At(0).has_value());
  EXPECT_EQ(frame.Latest().x_m, 0.0);
  for (int i = 0; i <= 100; ++i) frame.Add(Reading(i * 20'000'000, 0.01 * i, 0.0));  // 2 s at 50 Hz, 0.5 m/s
  EXPECT_NEAR(frame.At(1'990'000'000)->x_m, 0.995, 1e-9);                            // half way between the last two
  EXPECT_NEAR(frame.At(5'000'000'000)->x_m, 1.0, 1e-9);                              // beyond the last: the last
  // Older than a second: the oldest kept.
  EXPECT_NEAR(frame.At(0)->x_m, 0.5, 0.011);
  const nav::Pose2 map_pose = frame.Add(Reading(2'020'000'000, 1.01, 0.0));
  EXPECT_NEAR(map_pose.x_m, 2.01, 1e-9);
  EXPECT_NEAR(map_pose.y_m, 2.0, 1e-9);
}

// The pose follows each odometry reading as it is published, on the publisher's thread: the node's executor (here
// never run) is not woken for it.
TEST(LocalizationNodeTest, ThePoseFollowsEachOdometryReadingWithoutTheNodesThread) {
  drivers::ManualClock clock;
  Executor mapping("mapping", clock, Schedule::kLockstep);
  Bus bus;
  LocalizationOptions options;
  const nav::PinholeCamera no_camera{};
  LocalizationNode node(mapping, bus, options, nav::Pose2{5.0, 1.0, 0.0}, nav::Pose2{}, no_camera);
  node.Activate();
  auto& odometry = bus.Get(topics::kOdometry);
  auto& pose = bus.Get(topics::kPose);
  std::thread publisher([&] {
    for (int i = 1; i <= 10; ++i) {
      odometry.Publish(Reading(i * 20'000'000, 0.1 * i, 0.0));
      const auto now = pose.latest();
      ASSERT_NE(now, nullptr);
      EXPECT_EQ(now->stamp_ns, i * 20'000'000);
      EXPECT_NEAR(now->pose.x_m, 5.0 + 0.1 * i, 1e-9);
      EXPECT_NEAR(now->pose.y_m, 1.0, 1e-9);
    }
  });
  publisher.join();
}

}  // namespace
}  // namespace corridor::server
