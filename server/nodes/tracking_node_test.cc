#include "server/nodes/tracking_node.h"

#include <gtest/gtest.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// A 160 x 120 camera 0.3 m above the floor looking straight ahead.
nav::PinholeCamera ForwardCamera() {
  nav::PinholeCamera camera{160, 120, 80.0, 80.0, 80.0, 60.0, Eigen::Isometry3d::Identity(), {}};
  Eigen::Matrix3d base_R_optical;
  base_R_optical.col(0) = Eigen::Vector3d(0.0, -1.0, 0.0);  // optical x: right
  base_R_optical.col(1) = Eigen::Vector3d(0.0, 0.0, -1.0);  // optical y: down
  base_R_optical.col(2) = Eigen::Vector3d(1.0, 0.0, 0.0);   // optical z: forward
  camera.base_T_camera.linear() = base_R_optical;
  camera.base_T_camera.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
  return camera;
}

TEST(TrackingNodeTest, WithoutALaserItTracksFromDepthFramesAndSaysWhenAFrameIsWrong) {
  drivers::ManualClock clock;
  Executor mapping("mapping", clock, Schedule::kLockstep);
  Bus bus;
  TrackingSource source;
  source.camera = ForwardCamera();
  TrackingNode node(mapping, bus, source, nav::MovingObjectOptions{}, nav::TrafficOptions{});
  node.Activate();
  EXPECT_NE(node.Status()["message"].get<std::string>().find("depth frames"), std::string::npos) << node.Status();
  bus.Get(topics::kPose).Publish(StampedPose{0, nav::Pose2{}});

  // A frame of another size than the camera's: the node says so and publishes nothing.
  drivers::RgbdFrame wrong;
  wrong.stamp_ns = drivers::FromSeconds(1.0);
  wrong.depth_mm = cv::Mat::zeros(10, 10, CV_16UC1);
  bus.Get(topics::kRgbd).Publish(wrong);
  mapping.Poll();
  const nlohmann::json degraded = node.Status();
  EXPECT_EQ(degraded["health"], "degraded") << degraded;
  EXPECT_EQ(bus.Get(topics::kTrackedObjects).latest(), nullptr);

  // Someone 1.5 m ahead crossing from left to right (a patch of the image 20 columns wide, 3 columns further right
  // each tenth of a second: about 0.56 m/s), with nothing else in view.
  for (int k = 2; k <= 14; ++k) {
    drivers::RgbdFrame frame;
    frame.stamp_ns = drivers::FromSeconds(0.1 * k);
    frame.depth_mm = cv::Mat::zeros(120, 160, CV_16UC1);
    const int left = 40 + 3 * k;
    frame.depth_mm(cv::Rect(left, 20, 20, 50)).setTo(1500);
    clock.Set(frame.stamp_ns);
    bus.Get(topics::kRgbd).Publish(frame);
    mapping.Poll();
  }
  const nlohmann::json ok = node.Status();
  EXPECT_EQ(ok["health"], "ok") << ok;
  EXPECT_NE(ok["message"].get<std::string>().find("1 moving"), std::string::npos) << ok;
  const auto tracked = bus.Get(topics::kTrackedObjects).latest();
  ASSERT_NE(tracked, nullptr);
  ASSERT_EQ(tracked->surroundings.objects.size(), 1u);
  const nav::TrackedObject& person = tracked->surroundings.objects.front();
  EXPECT_TRUE(person.moving);
  EXPECT_NEAR(person.position.x(), 1.5, 0.1);
  EXPECT_LT(person.velocity.y(), -0.4);  // to the robot's right
}

}  // namespace
}  // namespace corridor::server
