// MORP ground segmentation on raw depth images (DPoom: Kim et al., "DPoom: An Exploration Agent for Home Robot
// Navigation", IEEE Access 2022, section III-D, equations (2)-(3)).
//
// Virtual lanes run straight ahead on the floor, side by side across the robot's width. Each lane projects to a
// line in the image; MORP scans it bottom-up from its start pixel s_j, turns each pixel into metric (r, z) (forward
// distance and height in the base frame, through the intrinsics and the camera's mounting), and scores it as
//   score = w1 * |dz/dr| (local, against the previous valid pixel) + w2 * |dz/dr| (against the start pixel s_j).
// The first pixel whose score exceeds C and whose height above s_j exceeds the step the robot can drive over is the
// lane's dead-end; its r is the lane's free distance.
//
// s_j starts at the lane's bottom pixel and moves up to every pixel that scores as floor, so the second term is the
// slope of a rise from its own base. Measured from the robot's feet instead, an obstacle 1.5 m away rises only a few
// centimetres over a metre and a half (slope ~0.03) and depth noise swamps the local term (~4 mm rise per image row
// against ~1 cm of range noise): the wall would be missed. From its base, its slope is above 5. A gentle ramp stays
// drivable because s_j climbs with it, and step height is measured from the base of the step, so a small error in
// the camera's calibrated height or tilt does not turn far floor into obstacles.
//
// Where the published reference code differs from the paper (two slope tests, no weights, no metric conversion,
// pixel thresholds), this follows the paper, with three additions: the step height is a metric threshold that may be
// changed at run time; a drop below the floor (stairs, a ledge) is a dead-end too, by height alone (the lower floor
// beyond an edge looks like gentle slope from above); and holes (0 depth) are skipped,
// while a lane with no valid pixel near the robot is a dead-end at the camera's minimum range (blind means stop).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"

namespace corridor::nav {

struct MorpOptions {
  int lanes = 0;  // 0: one lane per lane_width_m across span_m
  // The lanes' total width, centred on the robot: wider than the robot, so that what passes beside it was seen
  // (the local navigator steers on the lanes in front of its footprint and remembers the others).
  double span_m = 1.0;
  double lane_width_m = 0.1;
  double w1 = 0.5;               // weight of the local gradient
  double w2 = 0.5;               // weight of the gradient from the start pixel
  double score_threshold = 0.6;  // C: a weighted slope (rise over run); 0.6 is about 31 degrees
  double max_step_m = 0.03;      // height above (or below) the floor the robot drives over; run-time setting
  double max_drop_m = 0.05;      // anything this far below the floor is a drop, whatever its slope
  double min_range_m = 0.2;      // the camera's minimum range
  double max_range_m = 4.0;      // lanes are scanned out to this forward distance
  // No valid depth before this forward distance: the lane is blind. A stereo pair's lanes on its left side get the
  // distance its shadow adds (PinholeCamera::stereo).
  double blind_range_m = 0.6;
  int half_window_px = 2;  // each lane sample takes the nearest valid depth across 2k+1 columns
};

struct LaneResult {
  double offset_m = 0.0;         // the lane's centre, left of the robot's centre line
  double free_distance_m = 0.0;  // forward distance to the dead-end, or max_range_m when none
  bool dead_end = false;
  bool blind = false;                               // no valid depth near the robot
  Eigen::Vector2i pixel{-1, -1};                    // the dead-end pixel (u, v), when dead_end
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the dead-end in the base frame, when dead_end
};

// The lanes' centres, left of the robot's centre line, from left (+y) to right, evenly across span_m (the lanes of
// MORP and of the laser's lanes, nav/ground/laser_lanes.h).
std::vector<double> LaneOffsets(const MorpOptions& options);

// The lane (an index into LaneOffsets(options), `lanes` of them) whose centre line a point `y_m` left of the robot's
// centre lies on: within a quarter of the lanes' spacing of it, as MORP samples a line along each lane, not a band
// (a wall running beside the robot at the edge of the lanes it steers on is no dead-end ahead); -1 for none.
int LaneOnLine(const MorpOptions& options, int lanes, double y_m);

// How far ahead a lane `offset_m` left of the robot's centre is blind when it has no depth: blind_range_m, and as
// much farther as a stereo pair's shadow keeps the lane's floor from being measured where it enters the image.
double LaneBlindRange(const PinholeCamera& camera, const MorpOptions& options, double offset_m);

// The nearest dead-end among the lanes whose centre lies within half_width_m of the robot's centre line (the lanes
// in front of its footprint); +infinity when there is none.
double NearestDeadEnd(const std::vector<LaneResult>& lanes, double half_width_m);

class Morp {
 public:
  // Precomputes the lanes' pixels and rays for this camera. Throws std::invalid_argument for an unusable camera
  // (non-positive focal length or size) or options (non-positive widths, ranges out of order).
  Morp(const PinholeCamera& camera, const MorpOptions& options);

  // Segments one depth image (CV_16UC1 millimetres or CV_32FC1 metres, 0 or NaN for holes, the camera's size).
  // Throws std::invalid_argument for another type or size. Thread-compatible; allocation-free after the first call.
  const std::vector<LaneResult>& Process(const cv::Mat& depth);

  // The run-time step height (the paper's argument for an analytic method: no retraining to change it).
  void set_max_step_m(double metres) { options_.max_step_m = metres; }
  const MorpOptions& options() const { return options_; }
  const std::vector<LaneResult>& results() const { return results_; }  // the last Process's
  int lane_count() const { return static_cast<int>(lanes_.size()); }

 private:
  struct Sample {
    int u;                   // centre column
    int v;                   // row
    Eigen::Vector3f origin;  // camera centre, base frame
    Eigen::Vector3f ray;     // base-frame ray with unit optical depth
  };
  struct Lane {
    double offset_m;
    double blind_range_m;
    std::vector<Sample> samples;  // bottom-up
  };

  PinholeCamera camera_;
  MorpOptions options_;
  std::vector<Lane> lanes_;
  std::vector<LaneResult> results_;
};

}  // namespace corridor::nav
