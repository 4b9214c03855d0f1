#include "tools/slam_eval/heading_noise.h"

#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace corridor::tools {
namespace {

TEST(ThreeCorneredHatTest, SeparatesThreeEstimatesOwnNoise) {
  // The same headings seen through independent noise of 0.5, 0.1 and 0.3 (seeded), and 2 % of gross errors in one.
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> heading(-3.0, 3.0);
  std::vector<double> a;
  std::vector<double> b;
  std::vector<double> c;
  for (int i = 0; i < 20000; ++i) {
    const double truth = heading(random);
    a.push_back(truth + 0.5 * normal(random));
    b.push_back(truth + 0.1 * normal(random));
    c.push_back(truth + 0.3 * normal(random) + (i % 50 == 0 ? 2.0 : 0.0));
  }
  const HatSigmas s = ThreeCorneredHat(a, b, c);
  // The largest is recovered best; the smallest is a small difference of large variances: only bounded.
  EXPECT_NEAR(s.a, 0.5, 0.03);
  EXPECT_NEAR(s.c, 0.3, 0.05);
  EXPECT_LT(s.b, 0.15);
  EXPECT_EQ(s.count, 20000);
}

TEST(ThreeCorneredHatTest, DifferencesAreWrappedAngles) {
  // pi - 0.01 and -pi + 0.01 are 0.02 apart, not 2 pi.
  const std::vector<double> a{3.13, -3.13, 3.13, -3.13};
  const std::vector<double> b{-3.13, 3.13, -3.13, 3.13};
  const HatSigmas s = ThreeCorneredHat(a, b, b);
  EXPECT_LT(s.a, 0.05);
}

TEST(ThreeCorneredHatTest, RejectsSeriesOfDifferentLengths) {
  const std::vector<double> three{0.0, 1.0, 2.0};
  const std::vector<double> two{0.0, 1.0};
  EXPECT_THROW(ThreeCorneredHat(three, three, two), std::invalid_argument);
  EXPECT_THROW(ThreeCorneredHat(two, two, two), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::tools
