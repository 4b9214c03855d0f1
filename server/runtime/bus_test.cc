#include "server/runtime/bus.h"

#include <gtest/gtest.h>

#include <future>

namespace corridor::server {
namespace {

constexpr TopicName<nav::Twist2> kTwist{"twist"};
constexpr TopicName<StampedPose> kWrongType{"twist"};
constexpr TopicName<nav::Twist2> kLatchedTwist{"latched", true};
constexpr TopicName<nav::Twist2> kNotLatched{"latched"};
constexpr TopicName<nav::Twist2> kEveryTwist{"every", false, Delivery::kEvery};
constexpr TopicName<nav::Twist2> kNewestTwist{"every"};

// Waits until `executor` (running on its thread) has run everything posted to it so far.
void Drain(Executor& executor) {
  std::promise<void> drained;
  executor.Post([&] { drained.set_value(); });
  drained.get_future().wait();
}

// Publishes 0 to 99 on `topic` before `executor` runs, then runs it: a subscriber on it puts what it sees in `seen`.
void DeliverABacklog(Bus& bus, Executor& executor, TopicName<nav::Twist2> topic, std::vector<double>& seen) {
  bus.Get(topic).Subscribe(executor, [&seen](const auto& m) { seen.push_back(m->linear_mps); });
  for (int i = 0; i < 100; ++i) bus.Get(topic).Publish(nav::Twist2{static_cast<double>(i), 0.0});
  executor.Start();
  Drain(executor);
}

TEST(BusTest, SubscriberGetsMessagesOnItsExecutorAndLatestIsKept) {
  Bus bus;
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  executor.Start();
  std::promise<std::pair<double, std::thread::id>> got;
  bus.Get(kTwist).Subscribe(executor, [&](const auto& m) {
    got.set_value({m->linear_mps, std::this_thread::get_id()});
  });
  bus.Get(kTwist).Publish(nav::Twist2{0.25, 0.0});
  const auto [value, thread] = got.get_future().get();
  EXPECT_EQ(value, 0.25);
  EXPECT_NE(thread, std::this_thread::get_id());
  EXPECT_EQ(bus.Get(kTwist).latest()->linear_mps, 0.25);
  ASSERT_NE(bus.Find("twist"), nullptr);
  EXPECT_EQ((*bus.Find("twist")->LatestJson())["linear_mps"], 0.25);
  executor.Stop();
}

TEST(BusTest, SlowSubscriberSkipsToTheNewestMessage) {
  Bus bus;
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  // Publish 100 messages before the executor runs: the subscriber sees only the newest.
  std::vector<double> seen;
  DeliverABacklog(bus, executor, kTwist, seen);
  executor.Stop();
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0], 99.0);
}

TEST(BusTest, ATapSeesEveryMessageOnThePublishersThreadWhereASlowSubscriberSeesTheNewest) {
  Bus bus;
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  std::vector<std::thread::id> taps;
  std::vector<double> tapped;
  bus.Get(kTwist).Tap([&](const nav::Twist2& twist) {
    taps.push_back(std::this_thread::get_id());
    tapped.push_back(twist.linear_mps);
  });
  std::vector<double> seen;
  DeliverABacklog(bus, executor, kTwist, seen);  // the subscriber, its executor stopped, sees only the newest
  executor.Stop();
  EXPECT_EQ(taps, std::vector<std::thread::id>(100, std::this_thread::get_id()));
  ASSERT_EQ(tapped.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(tapped[static_cast<std::size_t>(i)], i);
  EXPECT_EQ(seen.size(), 1u);
}

TEST(BusTest, ATopicOfEventsDeliversEveryMessageInOrderToASlowSubscriber) {
  Bus bus;
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  std::vector<double> seen;
  DeliverABacklog(bus, executor, kEveryTwist, seen);
  bus.Get(kEveryTwist).Publish(nav::Twist2{100.0, 0.0});
  Drain(executor);
  executor.Stop();
  ASSERT_EQ(seen.size(), 101u);
  for (int i = 0; i <= 100; ++i) EXPECT_EQ(seen[static_cast<std::size_t>(i)], i);
}

TEST(BusTest, ALatchedTopicGivesALateSubscriberItsLatestMessageThenTheNextOnes) {
  Bus bus;
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kLockstep);
  std::vector<double> early;
  std::vector<double> late;
  std::vector<double> plain;
  bus.Get(kLatchedTwist).Subscribe(executor, [&](const auto& m) { early.push_back(m->linear_mps); });
  bus.Get(kLatchedTwist).Publish(nav::Twist2{1.0, 0.0});
  bus.Get(kTwist).Publish(nav::Twist2{1.0, 0.0});
  executor.Poll();
  bus.Get(kLatchedTwist).Subscribe(executor, [&](const auto& m) { late.push_back(m->linear_mps); });
  bus.Get(kTwist).Subscribe(executor, [&](const auto& m) { plain.push_back(m->linear_mps); });
  executor.Poll();
  bus.Get(kLatchedTwist).Publish(nav::Twist2{2.0, 0.0});
  executor.Poll();
  EXPECT_EQ(early, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(late, (std::vector<double>{1.0, 2.0}));
  EXPECT_TRUE(plain.empty());  // not latched: only what comes after
}

TEST(BusDeathTest, SameNameWithAnotherTypeIsABug) {
  Bus bus;
  bus.Get(kTwist);
  EXPECT_DEATH(bus.Get(kWrongType), "DEMAND");
}

TEST(BusDeathTest, SameNameWithAnotherDeliveryIsABug) {
  Bus bus;
  bus.Get(kEveryTwist);
  EXPECT_DEATH(bus.Get(kNewestTwist), "DEMAND");
}

TEST(BusDeathTest, SameNameLatchedAndNotIsABug) {
  Bus bus;
  bus.Get(kLatchedTwist);
  EXPECT_DEATH(bus.Get(kNotLatched), "DEMAND");
}

}  // namespace
}  // namespace corridor::server
