// Floor detection by RANSAC plane fitting on a depth image (the ASNS stereovision system's floor detection;
// Fischler and Bolles, CACM 1981), refined by least squares on the inliers. From the floor plane in the optical frame
// it calibrates the camera's height above the floor, its downward tilt and its roll, which MORP's metric conversion
// depends on.
#pragma once

#include <optional>
#include <random>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"

namespace corridor::nav {

struct FloorFitOptions {
  int iterations = 200;
  double inlier_threshold_m = 0.015;
  int stride_px = 4;                   // sample every stride-th pixel of every stride-th row
  double max_range_m = 4.0;            // farther points are too noisy to help
  double max_normal_angle_deg = 45.0;  // the floor's normal must be within this of the optical frame's "up" (-y)
  double min_inlier_fraction = 0.3;    // of the sampled points in the image's lower half
};

struct FloorFit {
  Eigen::Vector3d normal;  // unit, optical frame, pointing up (away from the floor)
  double offset = 0.0;     // plane: normal . p + offset = 0
  double camera_height_m = 0.0;
  double tilt_rad = 0.0;  // optical axis below the horizontal (pitch down)
  double roll_rad = 0.0;  // image x axis rotated about the optical axis
  int inliers = 0;
  double inlier_fraction = 0.0;
};

// Fits the floor in the lower half of `depth` (CV_16UC1 mm or CV_32FC1 m) seen through `camera`'s intrinsics (its
// mounting is not used: that is what is measured). nullopt when no plane with enough support looks like a floor.
std::optional<FloorFit> FitFloor(const cv::Mat& depth, const PinholeCamera& camera, const FloorFitOptions& options,
                                 std::mt19937& rng);

// The camera mounting in the base frame implied by a fit (height, tilt, roll; x offset and yaw kept from `nominal`).
Eigen::Isometry3d MountingFromFloor(const FloorFit& fit, const Eigen::Isometry3d& nominal);

}  // namespace corridor::nav
