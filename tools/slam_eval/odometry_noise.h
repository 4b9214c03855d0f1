// Wheel odometry made from a trajectory: the "corrected" CARMEN logs carry no raw odometry (their odometry fields
// repeat the corrected pose), so corridor-slam-eval drives a noisy odometry along the corrected motion between scans,
// each step read with a seeded random error on its length and heading change, and a bias that accumulates as real
// wheels' does (a scale error, a heading drift per metre).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::tools {

struct OdometryNoise {
  double translation_sigma = 0.05;           // of each move's length (5 %)
  double rotation_sigma = 0.0349;            // rad per rad turned (2 degrees per radian)
  double scale_error = 0.02;                 // every length read 2 % long
  double heading_drift_rad_per_m = 0.01745;  // 1 degree of heading lost per metre driven
  // All four multiplied by `factor` (0: perfect odometry).
  OdometryNoise Scaled(double factor) const {
    return {translation_sigma * factor, rotation_sigma * factor, scale_error * factor,
            heading_drift_rad_per_m * factor};
  }
};

// The odometry's reading at each pose of `truth` (starting at truth[0]), with `noise`, seeded.
std::vector<nav::Pose2> MakeOdometry(const std::vector<nav::Pose2>& truth, const OdometryNoise& noise,
                                     std::uint64_t seed);

}  // namespace corridor::tools
