// ASNS's floor detection (AFDS; the ASNS paper's section 4.3, Table 13) on a depth image: the floor and the planes on
// it by recursive RANSAC, per region of a grid over the image (3 x 2 to 12 x 9), giving each region's floor and the
// height of what stands in it; and, from the same points, the lanes MORP gives (nav/ground/morp.h), so that the
// depth path can take either as its ground test.
//
// The paper is not in the tree; this follows the description of it, and chooses what it leaves open
// (docs/asns.md, "AFDS"):
//   1. The frame's floor: RANSAC over all the points for the plane with the most support whose normal is within
//      max_floor_angle_deg of the base's up and which passes within floor_search_m of the floor the camera's mounting
//      gives (a table top is a horizontal plane too), refined by least squares. None found: the mounting's floor.
//   2. Per region, its own floor first: the best-supported horizontal plane within floor_tolerance_m of the frame's
//      floor (a ramp, a floor not quite flat), at inlier_m (a low camera sees the floor at a grazing angle: depth
//      noise, along the rays, moves its points little up or down). Then recursively the plane with the most support
//      among the region's points left, refined, its points taken out, until max_planes or too few points are left, at
//      an inlier distance that grows with the region's range as depth noise does (inlier_m + noise_b_per_m r^2: a face
//      seen head-on has its noise across it).
//   3. A region's obstacles are its planes higher than max_step_m above its floor: a horizontal one (a box's top)
//      stands at its mean height, any other (a face) at its highest pixel (followed up the image pixel by pixel);
//      where the pixel above is no level top at that height, half a pixel row higher (the face's edge lies between
//      that row and the next one up, which missed it).
//   4. A point higher than max_step_m above its region's floor, or lower than max_drop_m below it, is an obstacle; a
//      lane is a dead-end at the nearest obstacle point on its line with another within obstacle_run_m beyond it
//      (one point alone is a stereo pair's mismatch as often as a thing), blind as MORP's lanes are.
#pragma once

#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/plane_fit.h"
#include "nav/ground/morp.h"

namespace corridor::nav {

struct AfdsOptions {
  int grid_columns = 6;  // the regions across the image (ASNS: 3 to 12)
  int grid_rows = 4;     // and down it (ASNS: 2 to 9)
  int stride_px = 2;     // every stride-th pixel of every stride-th row is a point
  double min_range_m = 0.2;
  double max_range_m = 5.5;           // farther points are left out
  int iterations = 50;                // RANSAC draws per plane
  double inlier_m = 0.01;             // a point this near a plane is on it, at the camera...
  double noise_b_per_m = 0.0019;      // ...and this times the range squared farther (a D435's depth noise)
  int max_planes = 4;                 // per region
  int min_plane_points = 12;          // a plane with fewer points is not one
  double max_floor_angle_deg = 10.0;  // a horizontal plane's normal is within this of up
  double floor_search_m = 0.1;        // the frame's floor passes within this of the mounting's floor
  double floor_tolerance_m = 0.02;    // a region's horizontal plane this near the frame's floor is its floor
  double max_step_m = 0.03;           // higher: an obstacle (MorpOptions::max_step_m, run-time setting)
  double max_drop_m = 0.05;           // lower than the floor by this: a drop
  double obstacle_run_m = 0.15;       // a lane's dead-end has a second obstacle point within this beyond it
  unsigned seed = 1;                  // of the RANSAC draws
};

struct AfdsCell {
  int column = 0;  // in the grid, from the image's left
  int row = 0;     // and top
  int points = 0;
  int planes = 0;                  // found in it, its floor included
  bool own_floor = false;          // it has a floor plane of its own (else the frame's floor is its)
  double floor_height_m = 0.0;     // its floor above the frame's floor, at its floor points' centre
  double obstacle_height_m = 0.0;  // the highest obstacle plane's top above its floor (0: none)
  double obstacle_range_m = 0.0;   // that plane's nearest point, forward of the robot
};

struct AfdsFrame {
  bool floor_found = false;                // else `floor` is the mounting's
  Plane floor;                             // base frame, normal up
  std::vector<AfdsCell> cells;             // row-major over the grid
  std::vector<Eigen::Vector3f> obstacles;  // (x, y) base frame and height above its region's floor
  std::vector<LaneResult> lanes;           // as MORP's, left to right
};

class Afds {
 public:
  // `lanes`: the lanes' layout, range and blind range (MORP's options; its step and drop heights are `options`').
  // Throws std::invalid_argument for an unusable camera, a grid outside 1 x 1 to 32 x 32, or bad ranges.
  Afds(const PinholeCamera& camera, const AfdsOptions& options, const MorpOptions& lanes);

  // One depth image (CV_16UC1 millimetres or CV_32FC1 metres, 0 or NaN for holes, the camera's size; else
  // std::invalid_argument). Thread-compatible; reuses its buffers.
  const AfdsFrame& Process(const cv::Mat& depth);

  void set_max_step_m(double metres) { options_.max_step_m = metres; }
  const AfdsOptions& options() const { return options_; }
  int lane_count() const { return static_cast<int>(lane_offsets_.size()); }

 private:
  struct Point {
    Eigen::Vector3d p;  // base frame
    int region;
    int u;  // its pixel
    int v;
  };
  // Steps 2 and 3 for one region's points (indices into points_, which it takes out as it fits them): its cell, and
  // its floor.
  Plane FitRegion(std::vector<int>& members, AfdsCell& cell, const cv::Mat& depth);
  // The height of the top edge of a face (its points' indices, its plane; `depth` the frame's) above the frame's
  // floor.
  double FaceTop(const std::vector<int>& face, const Plane& plane, const cv::Mat& depth) const;
  // Above the step the robot drives over, or below the drop it must not: an obstacle.
  bool Obstacle(float height) const { return height > options_.max_step_m || height < -options_.max_drop_m; }
  // Step 4's lanes, from the points' heights above their regions' floors (heights_).
  void FillLanes();

  PinholeCamera camera_;
  AfdsOptions options_;
  MorpOptions lane_options_;
  std::vector<double> lane_offsets_;
  std::vector<double> lane_blind_m_;   // per lane (LaneBlindRange)
  std::vector<Eigen::Vector3f> rays_;  // per pixel, base frame, unit optical depth
  std::vector<int> region_of_pixel_;   // -1: in a stereo pair's shadow (no true depth: a depth there is a mismatch)
  std::mt19937 rng_;
  std::vector<Point> points_;
  std::vector<Eigen::Vector3d> cloud_;                             // points_' positions, for the frame's floor
  std::vector<std::vector<int>> regions_;                          // per region, its points left to fit
  std::vector<Eigen::Vector3d> positions_;                         // a region's, for RANSAC
  std::vector<int> on_plane_;                                      // the points a plane took
  std::vector<Plane> region_floor_;                                // per region, its floor
  std::vector<float> heights_;                                     // per point, above its region's floor
  std::vector<std::vector<std::pair<float, float>>> lane_points_;  // per lane, its points' (x, height)
  AfdsFrame frame_;
};

}  // namespace corridor::nav
