#include "face/events.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace corridor::face {
namespace {

constexpr drivers::TimeNs kSecond = 1'000'000'000;

Detection Person(int track, double x) {
  Detection d;
  d.label = "person";
  d.score = 0.9;
  d.track_id = track;
  d.position = Eigen::Vector3d(x, 0.0, 0.9);
  d.source = "sim";
  return d;
}

std::vector<EventType> Types(const std::vector<RobotEvent>& events) {
  std::vector<EventType> out;
  for (const RobotEvent& e : events) out.push_back(e.type);
  return out;
}

TEST(EventWatchTest, NamesRoundTrip) {
  for (int i = 0; i < kEventTypeCount; ++i) {
    const auto type = static_cast<EventType>(i);
    EXPECT_EQ(EventTypeFromString(ToString(type)), type);
  }
  EXPECT_FALSE(EventTypeFromString("person"));
  EXPECT_THROW(EventWatch({.person_left_after_s = -1.0}), std::invalid_argument);
}

TEST(EventWatchTest, APersonIsDetectedOnceAndLeavesAfterBeingUnseenForAWhile) {
  EventWatch watch;
  Situation s{.now_ns = 0};
  auto events = watch.Update(s, {Person(7, 2.0)});
  ASSERT_EQ(Types(events), std::vector{EventType::kPersonDetected});
  EXPECT_EQ(events[0].person->track_id, 7);
  s.now_ns = kSecond / 5;
  EXPECT_TRUE(watch.Update(s, {Person(7, 1.8), Person(8, 3.0)}).size() == 1);  // 8 is new, 7 is not
  // 7 missed for a second (a detector's miss) is still there; then gone for two seconds it has left.
  s.now_ns = kSecond;
  EXPECT_TRUE(watch.Update(s, {Person(8, 3.0)}).empty());
  s.now_ns = kSecond * 2 + kSecond / 5;
  events = watch.Update(s, {Person(8, 3.0)});
  ASSERT_EQ(Types(events), std::vector{EventType::kPersonLeft});
  EXPECT_EQ(events[0].person->track_id, 7);
  EXPECT_DOUBLE_EQ(events[0].person->position->x(), 1.8);  // where it was last seen
  // Faces and untracked detections are not people coming and going.
  Detection face = Person(9, 1.0);
  face.label = "face";
  Detection untracked = Person(0, 1.0);
  EXPECT_TRUE(watch.Update(s, {Person(8, 3.0), face, untracked}).empty());
}

TEST(EventWatchTest, AMissionsEndIsNewsOnlyWhenSeenHappening) {
  EventWatch watch;
  // A mission that had failed before the first sample (restored from the database) is not news.
  Situation s{.now_ns = 0, .mission = MissionPhase::kFailed, .mission_id = "old"};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s = {.now_ns = kSecond, .mission = MissionPhase::kActive, .mission_id = "m1", .place = "kitchen"};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = 2 * kSecond;
  s.mission = MissionPhase::kSucceeded;
  auto events = watch.Update(s, {});
  ASSERT_EQ(Types(events), std::vector{EventType::kMissionSucceeded});
  EXPECT_EQ(events[0].mission_id, "m1");
  EXPECT_EQ(events[0].place, "kitchen");
  s.now_ns = 3 * kSecond;
  EXPECT_TRUE(watch.Update(s, {}).empty());  // once
  // A mission that started and failed between two samples still counts; a canceled one is not news.
  s = {.now_ns = 4 * kSecond, .mission = MissionPhase::kFailed, .mission_id = "m2", .mission_error = "no path"};
  events = watch.Update(s, {});
  ASSERT_EQ(Types(events), std::vector{EventType::kMissionFailed});
  EXPECT_EQ(events[0].detail, "no path");
  s = {.now_ns = 5 * kSecond, .mission = MissionPhase::kActive, .mission_id = "m3"};
  watch.Update(s, {});
  s.mission = MissionPhase::kCanceled;
  EXPECT_TRUE(watch.Update(s, {}).empty());
}

TEST(EventWatchTest, BlockedOncePerBlockingAfterAWhile) {
  EventWatch watch({.blocked_after_s = 3.0});
  Situation s{.now_ns = 0, .mission = MissionPhase::kActive, .mission_id = "m1", .person_blocking = true};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = 2 * kSecond;
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = 3 * kSecond;
  auto events = watch.Update(s, {});
  ASSERT_EQ(Types(events), std::vector{EventType::kBlocked});
  EXPECT_EQ(events[0].detail, "person");
  s.now_ns = 10 * kSecond;
  EXPECT_TRUE(watch.Update(s, {}).empty());
  // The way clears, then the mission holds the robot still: a new blocking.
  s.person_blocking = false;
  s.now_ns = 11 * kSecond;
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.waiting = true;
  watch.Update(s, {});
  s.now_ns = 14 * kSecond;
  events = watch.Update(s, {});
  ASSERT_EQ(Types(events), std::vector{EventType::kBlocked});
  EXPECT_EQ(events[0].detail, "waiting");
  // Without a mission, a person in front is not blocking anything.
  EventWatch idle({.blocked_after_s = 0.0});
  EXPECT_TRUE(idle.Update({.now_ns = 0, .person_blocking = true}, {}).empty());
}

TEST(EventWatchTest, LostFaultAndBumpFireOnTheirRisingEdges) {
  EventWatch watch;
  Situation s{.now_ns = 0, .fault = true, .fault_detail = "camera: no frames for 1.0 s"};
  auto events = watch.Update(s, {});  // already stopped at the first sample: news
  ASSERT_EQ(Types(events), std::vector{EventType::kFault});
  EXPECT_EQ(events[0].detail, "camera: no frames for 1.0 s");
  s.now_ns = kSecond;
  s.bumped = true;
  s.lost = true;
  EXPECT_EQ(Types(watch.Update(s, {})), (std::vector{EventType::kLost, EventType::kBump}));
  s.now_ns = 2 * kSecond;
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s = {.now_ns = 3 * kSecond};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = 4 * kSecond;
  s.bumped = true;
  EXPECT_EQ(Types(watch.Update(s, {})), std::vector{EventType::kBump});
}

TEST(EventWatchTest, EachThingAMissionWaitsForAtADoorOrALiftIsNewsOnce) {
  EventWatch watch;
  Situation s{.now_ns = 0, .mission = MissionPhase::kActive, .mission_id = "m1"};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.waiting_for = "door d1 to open";
  for (int i = 1; i <= 3; ++i) {
    s.now_ns = i * kSecond;
    const auto events = watch.Update(s, {});
    if (i == 1) {
      ASSERT_EQ(Types(events), std::vector{EventType::kWaiting});
      EXPECT_EQ(events[0].detail, "door d1 to open");
      EXPECT_EQ(events[0].mission_id, "m1");
    } else {
      EXPECT_TRUE(events.empty()) << "still the same door";
    }
  }
  s.now_ns = 4 * kSecond;
  s.waiting_for = "lift east to come with its door open";
  EXPECT_EQ(Types(watch.Update(s, {})), std::vector{EventType::kWaiting});
  s.now_ns = 5 * kSecond;
  s.waiting_for.clear();
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = 6 * kSecond;
  s.waiting_for = "door d1 to open";  // the same door again, after it was through: news again
  EXPECT_EQ(Types(watch.Update(s, {})), std::vector{EventType::kWaiting});
}

TEST(EventWatchTest, ALowBatteryIsNewsOnceUntilItChargesOrRisesAgain) {
  EventWatch watch({.battery_low_percent = 20.0});
  Situation s{.now_ns = 0, .battery_percent = 25.0};
  EXPECT_TRUE(watch.Update(s, {}).empty());
  s.now_ns = kSecond;
  s.battery_percent = 19.6;
  const auto low = watch.Update(s, {});
  ASSERT_EQ(Types(low), std::vector{EventType::kBatteryLow});
  EXPECT_EQ(low[0].detail, "20 %");
  // Hovering round the threshold is not news again.
  for (const double percent : {20.5, 19.8, 21.0, 18.0}) {
    s.now_ns += kSecond;
    s.battery_percent = percent;
    EXPECT_TRUE(watch.Update(s, {}).empty()) << percent;
  }
  // Charged on the dock, then off it and low again: news.
  s.now_ns += kSecond;
  s.charging = true;
  EXPECT_TRUE(watch.Update(s, {}).empty()) << "charging";
  s.now_ns += kSecond;
  s.charging = false;
  s.battery_percent = 17.0;
  EXPECT_EQ(Types(watch.Update(s, {})), std::vector{EventType::kBatteryLow});
  // A base that reports no battery, and a threshold of 0, tell nothing.
  EventWatch never({.battery_low_percent = 0.0});
  EXPECT_TRUE(never.Update({.now_ns = 0, .battery_percent = 0.0}, {}).empty());
  EXPECT_TRUE(watch.Update({.now_ns = 100 * kSecond}, {}).empty());
  EXPECT_THROW(EventWatch({.battery_low_percent = 101.0}), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::face
