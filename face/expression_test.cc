#include "face/expression.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace corridor::face {
namespace {

using drivers::FromSeconds;

// The machine's expression after updates every 0.2 s from `from_s` to `to_s` with the situation `s` (its time set).
Expression Hold(ExpressionMachine& m, Situation s, double from_s, double to_s) {
  Expression e = m.current();
  for (double t = from_s; t <= to_s + 1e-9; t += 0.2) {
    s.now_ns = FromSeconds(t);
    e = m.Update(s).expression;
  }
  return e;
}

Situation At(double t_s) { return {.now_ns = FromSeconds(t_s)}; }

Situation OnMission(double t_s, MissionPhase phase, std::string id = "m1") {
  Situation s = At(t_s);
  s.mission = phase;
  s.mission_id = std::move(id);
  return s;
}

TEST(ExpressionMachineTest, EveryExpressionHasANameThatReadsBack) {
  for (int i = 0; i < kExpressionCount; ++i) {
    const auto e = static_cast<Expression>(i);
    EXPECT_EQ(ExpressionFromString(ToString(e)), e);
  }
  EXPECT_FALSE(ExpressionFromString("grumpy"));
  EXPECT_EQ(ToString(Expression::kConfused), "confused");
}

TEST(ExpressionMachineTest, ABumpSurprisesForTheHoldTimeThenTheFaceReturns) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(1), .moving = true}).expression, Expression::kFocused);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(2), .bumped = true}).expression, Expression::kSurprised);
  EXPECT_EQ(m.Update(At(3.9)).expression, Expression::kSurprised);
  EXPECT_EQ(m.Update(At(4.1)).expression, Expression::kNeutral);
}

TEST(ExpressionMachineTest, StartsAwakeWhateverTheClockReads) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update(At(86400)).expression, Expression::kNeutral);
}

TEST(ExpressionMachineTest, ChargingIsSleepyAtOnceUntilTheRobotSetsOff) {
  ExpressionMachine m;
  Situation charging = At(0);
  charging.charging = true;
  EXPECT_EQ(Hold(m, charging, 0.0, 2.0), Expression::kSleepy);  // not after sleepy_after_s: at once
  Situation leaving = OnMission(3.0, MissionPhase::kActive, "m2");
  leaving.charging = true;  // the contacts still touch as it backs off
  EXPECT_EQ(Hold(m, leaving, 3.0, 5.0), Expression::kFocused);
  EXPECT_EQ(Hold(m, At(6.0), 6.0, 8.0), Expression::kNeutral);
}

TEST(ExpressionMachineTest, AFaultIsSadAndOutranksEverything) {
  ExpressionMachine m;
  Situation s = OnMission(0, MissionPhase::kActive);
  s.moving = s.bumped = s.fault = s.lost = s.person_blocking = true;
  EXPECT_EQ(m.Update(s).expression, Expression::kSad);
}

TEST(ExpressionMachineTest, ARobotThatDoesNotKnowWhereItIsIsConfusedUntilFound) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update({.now_ns = 0, .moving = true}).expression, Expression::kFocused);
  EXPECT_EQ(m.Update({.now_ns = 1, .lost = true, .person_near = true}).expression, Expression::kConfused);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(120.0), .lost = true}).expression, Expression::kConfused);  // not sleepy
  EXPECT_EQ(m.Update(At(121.0)).expression, Expression::kNeutral);
}

TEST(ExpressionMachineTest, OnAMissionFocusedThenHappyOnArrivalWithWhereItArrived) {
  ExpressionMachine m;
  EXPECT_EQ(Hold(m, OnMission(0, MissionPhase::kActive), 0, 10), Expression::kFocused);
  Situation arrived = OnMission(10.2, MissionPhase::kSucceeded);
  arrived.place = "kitchen";
  const FaceOutput out = m.Update(arrived);
  EXPECT_EQ(out.expression, Expression::kHappy);
  ASSERT_TRUE(out.say);
  EXPECT_EQ(out.say->kind, PhraseKind::kArrived);
  EXPECT_EQ(out.say->text, "I have arrived at the kitchen.");
  EXPECT_FALSE(m.Update(arrived).say);  // said once
  EXPECT_EQ(Hold(m, arrived, 10.4, 13.0), Expression::kHappy);
  EXPECT_EQ(Hold(m, arrived, 13.4, 14.0), Expression::kNeutral);
}

TEST(ExpressionMachineTest, AMissionThatEndedBeforeTheFirstUpdateIsNotNews) {
  ExpressionMachine m;
  const FaceOutput out = m.Update(OnMission(0, MissionPhase::kSucceeded));
  EXPECT_FALSE(out.say);
  EXPECT_EQ(out.expression, Expression::kNeutral);
}

TEST(ExpressionMachineTest, AMissionThatFailedLeavesItConfusedForAWhile) {
  ExpressionMachine m;
  Hold(m, OnMission(0, MissionPhase::kActive), 0, 2);
  EXPECT_EQ(m.Update(OnMission(2.2, MissionPhase::kFailed)).expression, Expression::kConfused);
  EXPECT_EQ(Hold(m, OnMission(0, MissionPhase::kFailed), 2.4, 7.0), Expression::kConfused);
  EXPECT_EQ(Hold(m, OnMission(0, MissionPhase::kFailed), 7.4, 8.0), Expression::kNeutral);
}

TEST(ExpressionMachineTest, BlockedByAPersonItIsWorriedAndSaysExcuseMeOnceAfterThreeSeconds) {
  ExpressionMachine m;
  Hold(m, OnMission(0, MissionPhase::kActive), 0, 2);
  Situation blocked = OnMission(2.2, MissionPhase::kActive);
  blocked.person_blocking = blocked.person_near = true;
  int said = 0;
  for (double t = 2.2; t < 8.0; t += 0.2) {
    blocked.now_ns = FromSeconds(t);
    const FaceOutput out = m.Update(blocked);
    EXPECT_EQ(out.expression, Expression::kWorried) << t;
    if (out.say) {
      EXPECT_EQ(out.say->kind, PhraseKind::kExcuseMe);
      EXPECT_GE(t, 5.2 - 1e-9);
      ++said;
    }
  }
  EXPECT_EQ(said, 1);
  // The person steps aside and comes back: a new blocking, a new "excuse me" three seconds later.
  Hold(m, OnMission(0, MissionPhase::kActive), 8.0, 9.0);
  int again = 0;
  for (double t = 9.2; t < 13.0; t += 0.2) {
    blocked.now_ns = FromSeconds(t);
    again += m.Update(blocked).say.has_value();
  }
  EXPECT_EQ(again, 1);
}

TEST(ExpressionMachineTest, AMissionHoldingTheRobotStillIsWorried) {
  ExpressionMachine m;
  Situation waiting = OnMission(0, MissionPhase::kPaused);
  waiting.waiting = true;
  EXPECT_EQ(m.Update(waiting).expression, Expression::kWorried);
}

TEST(ExpressionMachineTest, APersonLookingAtAnIdleRobotGetsASmileAndAGreetingNowAndThen) {
  ExpressionMachine m;
  Situation looking = At(0);
  looking.person_looking = looking.person_near = true;
  FaceOutput out = m.Update(looking);
  EXPECT_EQ(out.expression, Expression::kHappy);
  ASSERT_TRUE(out.say);
  EXPECT_EQ(out.say->kind, PhraseKind::kGreeting);
  int greetings = 0;
  for (double t = 0.2; t < 29.0; t += 0.2) {
    looking.now_ns = FromSeconds(t);
    greetings += m.Update(looking).say.has_value();
  }
  EXPECT_EQ(greetings, 0);  // not again within greeting_every_s
  looking.now_ns = FromSeconds(30.0);
  EXPECT_TRUE(m.Update(looking).say);
  // Not while it is busy.
  ExpressionMachine busy;
  Situation on_mission = OnMission(0, MissionPhase::kActive);
  on_mission.person_looking = true;
  EXPECT_FALSE(busy.Update(on_mission).say);
}

TEST(ExpressionMachineTest, IdleForAMinuteIsSleepyAndAPersonWakesIt) {
  ExpressionMachine m;
  EXPECT_EQ(m.Update(At(0)).expression, Expression::kNeutral);
  EXPECT_EQ(m.Update(At(59)).expression, Expression::kNeutral);
  EXPECT_EQ(m.Update(At(61)).expression, Expression::kSleepy);
  Situation near = At(62.5);
  near.person_near = true;
  EXPECT_EQ(m.Update(near).expression, Expression::kNeutral);
}

TEST(ExpressionMachineTest, ALessUrgentExpressionWaitsForTheShownOneToHaveBeenUpASecond) {
  // Moving and stopping every 0.2 s does not make the face flicker between focused and neutral.
  ExpressionMachine m;
  int changes = 0;
  Expression last = m.Update(At(0)).expression;
  for (int i = 1; i < 50; ++i) {
    const Expression e = m.Update({.now_ns = FromSeconds(0.2 * i), .moving = i % 2 == 0}).expression;
    changes += e != last;
    last = e;
  }
  EXPECT_LE(changes, 10);  // at most once a second
  // An alarm shows at once.
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(10.1), .bumped = true}).expression, Expression::kSurprised);
}

TEST(ExpressionMachineTest, AnExpressionAskedForShowsForItsHoldUnderWhatIsMoreUrgent) {
  ExpressionMachine m;
  m.Update(At(0));
  m.Show(Expression::kSad, 5.0, FromSeconds(1.0));
  EXPECT_EQ(Hold(m, OnMission(0, MissionPhase::kActive), 1.0, 5.8), Expression::kSad);
  EXPECT_EQ(m.Update({.now_ns = FromSeconds(6.0), .bumped = true}).expression, Expression::kSurprised);
  EXPECT_EQ(Hold(m, OnMission(0, MissionPhase::kActive), 8.2, 9.6), Expression::kFocused);
  EXPECT_THROW(m.Show(Expression::kHappy, -1.0, 0), std::invalid_argument);
}

TEST(ExpressionMachineTest, RejectsNegativeHoldTimes) {
  ExpressionOptions o;
  o.min_hold_s = -1.0;
  EXPECT_THROW(ExpressionMachine{o}, std::invalid_argument);
}

}  // namespace
}  // namespace corridor::face
