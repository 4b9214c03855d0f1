// How noisy is the reference? The "corrected" poses of the Radish logs are themselves the output of a scan matcher, so
// a relative pose error against them mixes our error with theirs. The three-cornered hat (Gray and Allan, "A method
// for estimating the frequency stability of an individual oscillator", 1974) separates the two: three estimates of the
// same quantities, here the heading change between consecutive scans, and the variances of their pairwise differences
// give each estimate's own variance, assuming their errors independent. Where two of the three share error (the SLAM
// trajectory and scan-to-scan matching share the matcher and the scans), the shared part is counted as the third's:
// the reference's figure is then an upper bound and the other two lower bounds. The smallest of the three is a small
// difference of larger variances, and only roughly known.
#pragma once

#include <span>

namespace corridor::tools {

struct HatSigmas {
  double a = 0.0;  // each estimate's own standard deviation, in the values' unit
  double b = 0.0;
  double c = 0.0;
  long count = 0;  // values used
};

// The standard deviation of each of three estimates a, b, c of the same values (angles in radians: differences are
// wrapped). Each difference's spread is taken robustly (1.4826 x the median absolute difference), so that a few
// failed matches do not dominate; a variance that comes out negative is reported as 0. Throws std::invalid_argument
// unless the three have the same length, at least 3.
HatSigmas ThreeCorneredHat(std::span<const double> a, std::span<const double> b, std::span<const double> c);

}  // namespace corridor::tools
