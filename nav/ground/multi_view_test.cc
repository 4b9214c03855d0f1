#include "nav/ground/multi_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace corridor::nav {
namespace {

PinholeCamera Camera() {
  PinholeCamera k;
  k.width = 160;
  k.height = 120;
  k.fx = k.fy = 87.0;
  k.cx = 79.5;
  k.cy = 59.5;
  k.base_T_camera = CameraMount(0.1, 0.3, 0.0);
  return k;
}

// What the camera reads of a wall across x = wall_x (odometry frame) with the robot at `pose`, rounded to millimetres.
cv::Mat Wall(const PinholeCamera& k, const Pose2& pose, double wall_x) {
  const Eigen::Isometry3d odom_T_camera = pose.ToIsometry3() * k.base_T_camera;
  cv::Mat depth(k.height, k.width, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d ray = odom_T_camera.linear() * k.Ray(u, v);
      if (ray.x() <= 1e-6) continue;
      const double z = (wall_x - odom_T_camera.translation().x()) / ray.x();  // along the optical axis: ray's z is 1
      depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(1e3 * z));
    }
  }
  return depth;
}

int Readings(const cv::Mat& depth) { return cv::countNonZero(depth); }

TEST(MultiViewTest, AWallIsKeptFromItsSecondViewWhileTheRobotDrives) {
  const PinholeCamera k = Camera();
  MultiViewOptions options;
  options.enabled = true;
  MultiViewFilter filter(k, options);
  for (int n = 0; n < 5; ++n) {
    const Pose2 pose{0.04 * n, 0.01 * n, 0.02 * n};  // 15 frames a second at 0.6 m/s, turning
    cv::Mat depth = Wall(k, pose, 3.0);
    const int before = Readings(depth);
    ASSERT_GT(before, 15000);
    filter.Apply(depth, pose);
    if (n == 0) {
      EXPECT_EQ(Readings(depth), 0);  // seen once
    } else {
      EXPECT_GT(Readings(depth), 0.9 * before) << "frame " << n;
    }
  }
}

TEST(MultiViewTest, MismatchesThatMoveFromFrameToFrameAreDropped) {
  const PinholeCamera k = Camera();
  MultiViewOptions options;
  options.enabled = true;
  MultiViewFilter filter(k, options);
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> column(0, k.width - 1), row(0, k.height - 1), depth_mm(1500, 4500);
  int given = 0;
  int kept = 0;
  for (int n = 0; n < 20; ++n) {
    cv::Mat depth(k.height, k.width, CV_16UC1, cv::Scalar(0));
    for (int i = 0; i < 300; ++i)
      depth.at<std::uint16_t>(row(rng), column(rng)) = static_cast<std::uint16_t>(depth_mm(rng));
    given += Readings(depth);
    filter.Apply(depth, Pose2{});
    kept += Readings(depth);
  }
  // 1.6 % of the pixels a frame, each at a depth of its own: the few kept fell beside another's cell of the frames
  // before (a cell counts its neighbours' views).
  EXPECT_LT(kept, 0.1 * given);
}

TEST(MultiViewTest, NearReadingsPassAtOnce) {
  const PinholeCamera k = Camera();
  MultiViewOptions options;
  options.enabled = true;
  options.from_m = 1.0;
  MultiViewFilter filter(k, options);
  cv::Mat depth = Wall(k, Pose2{}, 0.9);
  const int before = Readings(depth);
  EXPECT_EQ(filter.Apply(depth, Pose2{}), 0);
  EXPECT_EQ(Readings(depth), before);
}

TEST(MultiViewTest, ACellNotSeenForAWindowIsForgotten) {
  const PinholeCamera k = Camera();
  MultiViewOptions options;
  options.enabled = true;
  options.views = 2;
  options.window = 3;
  MultiViewFilter filter(k, options);
  cv::Mat wall = Wall(k, Pose2{}, 3.0);
  cv::Mat first = wall.clone();
  filter.Apply(first, Pose2{});
  for (int n = 0; n < 3; ++n) {
    cv::Mat empty(k.height, k.width, CV_16UC1, cv::Scalar(0));
    filter.Apply(empty, Pose2{});
  }
  cv::Mat again = wall.clone();
  filter.Apply(again, Pose2{});
  EXPECT_EQ(Readings(again), 0);  // three frames later: the first view is out of the window
  for (int n = 0; n < 40; ++n) {
    cv::Mat empty(k.height, k.width, CV_16UC1, cv::Scalar(0));
    filter.Apply(empty, Pose2{});
  }
  EXPECT_EQ(filter.cells(), 0u);
}

TEST(MultiViewTest, OptionsThatCannotWorkAreRefused) {
  MultiViewOptions options;
  options.views = 4;  // more than the window
  EXPECT_THROW(MultiViewFilter(Camera(), options), std::invalid_argument);
  options = {};
  options.cell_m = 0.0;
  EXPECT_THROW(MultiViewFilter(Camera(), options), std::invalid_argument);
  EXPECT_THROW(MultiViewFilter(PinholeCamera{}, MultiViewOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
