#include "tools/train/dagger.h"

#include <gtest/gtest.h>

namespace corridor::tools {
namespace {

DaggerIteration Validated(double success, double collision, double loss) {
  DaggerIteration it;
  it.validation.success = success;
  it.validation.collision = collision;
  it.validation_loss = loss;
  return it;
}

TEST(DaggerTest, TheNetworkKeptSucceedsMostThenCollidesLeastThenStaysNearestTheExpert) {
  EXPECT_TRUE(BetterOnValidation(Validated(0.6, 0.4, 3.0), Validated(0.5, 0.1, 1.0)));
  EXPECT_TRUE(BetterOnValidation(Validated(0.5, 0.3, 3.0), Validated(0.5, 0.5, 1.0)));
  EXPECT_TRUE(BetterOnValidation(Validated(0.5, 0.5, 2.8), Validated(0.5, 0.5, 7.2)));
  // A tie in everything keeps the earlier network.
  EXPECT_FALSE(BetterOnValidation(Validated(0.5, 0.5, 2.8), Validated(0.5, 0.5, 2.8)));
}

}  // namespace
}  // namespace corridor::tools
