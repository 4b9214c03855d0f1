#include "tools/slam_eval/heading_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "nav/geometry/pose2.h"

namespace corridor::tools {
namespace {

// 1.4826 x the median of |x - y|: the standard deviation of x - y for normal errors, unmoved by a few outliers.
double RobustSigma(std::span<const double> x, std::span<const double> y) {
  std::vector<double> d(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = std::abs(nav::WrapAngle(x[i] - y[i]));
  const auto middle = d.begin() + static_cast<long>(d.size() / 2);
  std::nth_element(d.begin(), middle, d.end());
  return 1.4826 * *middle;
}

}  // namespace

HatSigmas ThreeCorneredHat(std::span<const double> a, std::span<const double> b, std::span<const double> c) {
  if (a.size() != b.size() || a.size() != c.size() || a.size() < 3) {
    throw std::invalid_argument("three-cornered hat: three series of the same length, at least 3");
  }
  const double ab = std::pow(RobustSigma(a, b), 2);
  const double ac = std::pow(RobustSigma(a, c), 2);
  const double bc = std::pow(RobustSigma(b, c), 2);
  const auto sigma = [](double variance) { return std::sqrt(std::max(0.0, variance)); };
  return {sigma((ab + ac - bc) / 2.0), sigma((ab + bc - ac) / 2.0), sigma((ac + bc - ab) / 2.0),
          static_cast<long>(a.size())};
}

}  // namespace corridor::tools
