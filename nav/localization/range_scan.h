// What localization and mapping read from a range sensor: where beams ended on something and where beams ran free,
// in the robot's base frame. The 2D laser and the depth camera's scan (nav/ground/depth_scan.h) both become one.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct RangeScan {
  Eigen::Vector2f origin = Eigen::Vector2f::Zero();  // the sensor, base frame
  std::vector<Eigen::Vector2f> hits;                 // beam ends on something, base frame
  std::vector<Eigen::Vector2f> misses;               // ends of beams that found nothing (free up to there), base frame
};

struct RangeLimits {
  double min_range_m = 0.05;  // shorter: the robot itself or a dirty window; dropped
  double max_range_m = 25.0;  // at or beyond: no return; a miss of miss_length_m
  double miss_length_m = 5.0;
};

// Where the base was when beam i was measured, in the base frame at the scan's stamp (for a sweep measured while the
// robot moved: drivers/laser2d.h's BeamAgeS with the odometry).
using BeamMotion = std::function<Pose2(std::size_t beam)>;

// A planar sweep (ranges[i] along angle_min_rad + i * increment_rad in the sensor frame, counter-clockwise from
// forward; NaN or +infinity for no return) from a sensor at base_T_sensor. With `motion`, each beam's end is put
// where it lies in the base frame at the stamp (the sweep's motion undone); the origin is the sensor at the stamp.
RangeScan ScanFromRanges(const Pose2& base_T_sensor, double angle_min_rad, double increment_rad,
                         std::span<const float> ranges_m, const RangeLimits& limits, const BeamMotion& motion = {});

// At most one point per square of side voxel_m (the first one met), in order: scans are dense near the sensor and
// sparse far away, and scan matching wants points spread evenly. Requires voxel_m > 0.
std::vector<Eigen::Vector2f> VoxelFilter(std::span<const Eigen::Vector2f> points, double voxel_m);

// `points` moved by `pose` (base frame into the pose's frame).
std::vector<Eigen::Vector2f> TransformPoints(const Pose2& pose, std::span<const Eigen::Vector2f> points);

}  // namespace corridor::nav
