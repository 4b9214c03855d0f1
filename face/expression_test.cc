#include "face/expression.h"

#include <gtest/gtest.h>

namespace corridor::face {
namespace {

using drivers::FromSeconds;

TEST(ExpressionMachineTest, ABumpSurprisesForTheHoldTimeThenTheFaceReturns) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(1), .moving = true}), Expression::kFocused);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(2), .bumped = true}), Expression::kSurprised);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(3.9)}), Expression::kSurprised);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(4.1)}), Expression::kNeutral);
}

TEST(ExpressionMachineTest, StartsAwakeWhateverTheClockReads) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(86400)}), Expression::kNeutral);
}

TEST(ExpressionMachineTest, AFaultOutranksEverything) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = 0, .moving = true, .bumped = true, .fault = true, .person_near = true}),
            Expression::kWorried);
}

TEST(ExpressionMachineTest, ARobotThatDoesNotKnowWhereItIsIsWorriedUntilFound) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = 0, .moving = true}), Expression::kFocused);
  EXPECT_EQ(m.Update({.now_ns = 1, .person_near = true, .lost = true}), Expression::kWorried);
  EXPECT_EQ(m.Update({.now_ns = drivers::FromSeconds(120.0), .lost = true}), Expression::kWorried);  // not sleepy
  EXPECT_EQ(m.Update({.now_ns = drivers::FromSeconds(121.0)}), Expression::kNeutral);
}

TEST(ExpressionMachineTest, IdleForAMinuteIsSleepyAndAPersonWakesIt) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(0)}), Expression::kNeutral);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(59)}), Expression::kNeutral);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(61)}), Expression::kSleepy);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(62), .person_near = true}), Expression::kHappy);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(63)}), Expression::kNeutral);
}

}  // namespace
}  // namespace corridor::face
