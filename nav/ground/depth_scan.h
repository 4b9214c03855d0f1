// A depth frame as a laser scan: for each image column, the nearest point that stands between min_height_m and
// max_height_m above the floor, on the floor plane in the base frame (what depthimage_to_laserscan does in ROS, with
// the camera's mounting height and tilt taken into account, so that a tilted camera's floor is not an obstacle).
//
// It lets the moving-object tracker (nav/tracking/moving_objects.h) follow people with the robot's only camera when
// no laser is fitted: the same clustering in (x, y, t) works on these points, within the camera's field of view.
// Written here: Debian packages no depthimage_to_laserscan outside ROS, and the loop is a few lines.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"
#include "nav/geometry/sensor_view.h"

namespace corridor::nav {

struct DepthScanOptions {
  double min_height_m = 0.1;  // lower: the floor and what the robot drives over
  double max_height_m = 1.8;  // higher: passed under
  double min_range_m = 0.2;
  double max_range_m = 4.0;  // farther, depth noise (and the nearest of a column's noisy pixels) puts walls off the map
  int row_step = 2;          // every row_step-th row is read (a person is many rows tall)
  // An object cut by the side of the image shows a part that slides as the robot turns, which a tracker takes for
  // motion: the run of neighbouring columns (points within segment_gap_m of each other) that touches either side
  // is dropped (0: kept). MORP still sees it; the tracker picks it up once it is wholly in view.
  double segment_gap_m = 0.15;
  // 0: a column's point is its nearest (what avoidance wants: nothing nearer is missed). Above 0: the mean of the
  // column's points within this of its nearest, which is what localization wants: the nearest of a column's noisy
  // pixels lies short of the wall by about two standard deviations of the depth noise (3-4 cm at 3 m).
  double average_within_m = 0.0;
};

// The scan the local navigator's obstacle memory takes (nav/safety/obstacle_memory.h): the image's sides kept (what
// the side cuts is still there to drive into) and out to 2 m (the memory keeps 1.5 m).
inline DepthScanOptions ForObstacleMemory(DepthScanOptions options) {
  options.segment_gap_m = 0.0;
  options.max_range_m = 2.0;
  return options;
}

class DepthScan {
 public:
  // Throws std::invalid_argument for a camera without size or focal length, or bad options.
  DepthScan(const PinholeCamera& camera, const DepthScanOptions& options);

  // The nearest point of each column that has one, base frame (x forward, y left), in column order, less the runs
  // touching the image's sides. `depth` is CV_16UC1 in millimetres of the camera's size (else
  // std::invalid_argument); 0 is a hole.
  const std::vector<Eigen::Vector2d>& Process(const cv::Mat& depth);
  // After Process: for each column with no point, where its ray meets max_range_m on the floor (base frame): nothing
  // stands there between the heights out to that range, as far as the camera saw (a column of holes counts too, as a
  // laser's beam without a return does). Localization and mapping read them as free space.
  const std::vector<Eigen::Vector2d>& misses() const { return misses_; }

  // The floor the scans cover (the image's width on the floor, out to max_range_m, less a stereo pair's shadow) with
  // the robot at world_T_base.
  SensorView View(const Pose2& world_T_base) const {
    return {world_T_base * base_T_view_, half_angle_rad_, options_.max_range_m, camera_.stereo, camera_.fx, camera_.cx};
  }

 private:
  PinholeCamera camera_;
  DepthScanOptions options_;
  std::vector<Eigen::Vector3f> rays_;  // per read pixel (row-major over the rows read), base frame, z-depth 1
  std::vector<float> nearest_;         // per column: squared horizontal range of its nearest point so far
  std::vector<Eigen::Vector2f> at_;    // per column: that point (or the mean, average_within_m)
  std::vector<int> count_;             // per column: the points averaged
  std::vector<Eigen::Vector2d> points_;
  std::vector<Eigen::Vector2d> misses_;
  std::vector<Eigen::Vector2d> column_end_;  // per column: its ray on the floor at max_range_m, base frame
  Pose2 base_T_view_;                        // the camera on the floor, x along its optical axis
  double half_angle_rad_ = 0.0;              // to the nearer side of the image, on the floor
};

}  // namespace corridor::nav
