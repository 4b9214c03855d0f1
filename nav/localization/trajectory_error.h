// How far an estimated trajectory is from the truth, as the SLAM benchmark of Kuemmerle et al. ("On measuring the
// accuracy of SLAM algorithms", Autonomous Robots 2009) measures it: by the error of relative poses between pairs of
// poses, which does not depend on where the estimate's frame is anchored; and, for localization in a known map, by
// the error of each pose.
#pragma once

#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct ErrorStats {
  double mean = 0.0;
  double std = 0.0;
  double max = 0.0;
  double rmse = 0.0;
  long count = 0;
};

struct RelativeError {
  ErrorStats translation_m;
  ErrorStats rotation_deg;
};

// Pairs (i, j), i < j, whose travel along the truth between them is at most max_travel_m: the error of
// estimate_i^-1 * estimate_j against truth_i^-1 * truth_j. Requires equal lengths (std::invalid_argument).
RelativeError LocalRelativeError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate,
                                 double max_travel_m = 2.0);

// Pairs whose true positions are within radius_m of each other after at least min_travel_m of travel between them:
// places the robot came back to, where the map must agree with itself.
RelativeError RevisitRelativeError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate,
                                   double radius_m = 1.0, double min_travel_m = 10.0);

// Each pose's error (no alignment: both in the same frame).
RelativeError AbsoluteError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate);

}  // namespace corridor::nav
