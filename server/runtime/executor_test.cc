#include "server/runtime/executor.h"

#include <gtest/gtest.h>

#include <future>
#include <stdexcept>
#include <string>
#include <vector>

namespace corridor::server {
namespace {

using drivers::FromSeconds;

TEST(LockstepTest, TimersFireOnTheSimulatedClockAndSkipWhatTheyMissed) {
  drivers::ManualClock clock;
  Executor executor("test", clock, Schedule::kLockstep);
  std::vector<double> ticks;
  PeriodicTimer timer(executor, std::chrono::milliseconds(100),
                      [&] { ticks.push_back(drivers::ToSeconds(clock.Now())); });
  for (int step = 1; step <= 30; ++step) {  // 0.3 s in 10 ms steps
    clock.Set(FromSeconds(0.01 * step));
    executor.Poll();
  }
  ASSERT_EQ(ticks.size(), 3u);
  EXPECT_NEAR(ticks[0], 0.1, 1e-9);
  EXPECT_NEAR(ticks[2], 0.3, 1e-9);
  // A jump of a whole second: one tick, not ten, and the next a period later.
  clock.Set(FromSeconds(1.3));
  executor.Poll();
  executor.Poll();
  EXPECT_EQ(ticks.size(), 4u);
  clock.Set(FromSeconds(1.39));
  executor.Poll();
  EXPECT_EQ(ticks.size(), 4u);
  clock.Set(FromSeconds(1.4));
  executor.Poll();
  EXPECT_EQ(ticks.size(), 5u);
  timer.Stop();
  clock.Set(FromSeconds(5.0));
  executor.Poll();
  EXPECT_EQ(ticks.size(), 5u);
}

TEST(LockstepTest, RunUntilIdleRunsWhatHandlersPostInAFixedOrderOfExecutors) {
  drivers::ManualClock clock;
  Executors executors(clock, Schedule::kLockstep);
  std::vector<std::string> order;
  // Posted to io first, then control, then sim: the sim executor is polled first, then control, ..., io last.
  executors.io.Post([&] { order.push_back("io"); });
  executors.control.Post([&] {
    order.push_back("control");
    executors.planning.Post([&] {
      order.push_back("planning");
      executors.control.Post([&] { order.push_back("control again"); });
    });
  });
  executors.sim.Post([&] { order.push_back("sim"); });
  EXPECT_EQ(executors.RunUntilIdle(), 5u);
  EXPECT_EQ(order, (std::vector<std::string>{"sim", "control", "planning", "io", "control again"}));
  EXPECT_EQ(executors.RunUntilIdle(), 0u);
}

TEST(LockstepTest, AHandlerThatThrowsIsDroppedAndTheRestRun) {
  drivers::ManualClock clock;
  Executor executor("test", clock, Schedule::kLockstep);
  int ran = 0;
  executor.Post([] { throw std::runtime_error("a bug"); });
  executor.Post([] { throw 42; });
  executor.Post([&] { ++ran; });
  PeriodicTimer timer(executor, std::chrono::milliseconds(10), [] { throw std::logic_error("a bad tick"); });
  clock.Set(FromSeconds(0.01));
  executor.Poll();
  EXPECT_EQ(ran, 1);
  EXPECT_EQ(executor.escaped(), 3u);
  clock.Set(FromSeconds(0.02));
  executor.Poll();  // the timer goes on ticking
  EXPECT_EQ(executor.escaped(), 4u);
}

TEST(ThreadsTest, AHandlerThatThrowsDoesNotEndTheThreadAndTimersTickInRealTime) {
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  executor.Start();
  executor.Post([] { throw std::runtime_error("a bug"); });
  std::promise<int> ticked;
  int ticks = 0;
  PeriodicTimer timer(executor, std::chrono::milliseconds(5), [&] {
    if (++ticks == 3) ticked.set_value(ticks);
  });
  auto future = ticked.get_future();
  ASSERT_EQ(future.wait_for(std::chrono::seconds(5)), std::future_status::ready);
  timer.Stop();
  std::promise<void> alive;
  executor.Post([&] { alive.set_value(); });
  EXPECT_EQ(alive.get_future().wait_for(std::chrono::seconds(5)), std::future_status::ready);
  EXPECT_EQ(executor.escaped(), 1u);
  executor.Stop();
}

TEST(LockstepTest, ADeadlineFiresOnceAtTheLatestTimeSet) {
  drivers::ManualClock clock;
  Executor executor("test", clock, Schedule::kLockstep);
  std::vector<double> fired;
  DeadlineTimer deadline(executor, [&] { fired.push_back(drivers::ToSeconds(clock.Now())); });
  const auto step_to = [&](double s) {
    clock.Set(FromSeconds(s));
    executor.Poll();
  };
  step_to(1.0);
  EXPECT_TRUE(fired.empty());  // not armed
  deadline.At(FromSeconds(1.08));
  step_to(1.05);
  deadline.At(FromSeconds(1.13));  // moved on: what it watched arrived again
  step_to(1.1);
  EXPECT_TRUE(fired.empty());
  step_to(1.13);
  ASSERT_EQ(fired.size(), 1u);
  EXPECT_NEAR(fired[0], 1.13, 1e-9);
  step_to(2.0);
  EXPECT_EQ(fired.size(), 1u);    // once
  deadline.At(FromSeconds(1.5));  // already past: at the next poll
  step_to(2.0);
  EXPECT_EQ(fired.size(), 2u);
  deadline.At(FromSeconds(2.5));
  deadline.Stop();
  step_to(3.0);
  EXPECT_EQ(fired.size(), 2u);
}

TEST(ThreadsTest, ADeadlineFiresInRealTimeAtTheLatestTimeSet) {
  const drivers::SteadyClock clock;
  Executor executor("test", clock, Schedule::kThreads);
  executor.Start();
  std::promise<drivers::TimeNs> fired;
  int count = 0;
  DeadlineTimer deadline(executor, [&] {
    if (++count == 1) fired.set_value(clock.Now());
  });
  drivers::TimeNs asked = 0;
  std::promise<void> armed;
  executor.Post([&] {
    deadline.At(clock.Now() + FromSeconds(0.02));
    asked = clock.Now() + FromSeconds(0.05);  // moved later before the first ran out
    deadline.At(asked);
    armed.set_value();
  });
  armed.get_future().wait();
  auto future = fired.get_future();
  ASSERT_EQ(future.wait_for(std::chrono::seconds(5)), std::future_status::ready);
  EXPECT_GE(future.get(), asked);
  deadline.Stop();
  std::promise<int> after;
  executor.Post([&] { after.set_value(count); });
  EXPECT_EQ(after.get_future().get(), 1);
  executor.Stop();
}

}  // namespace
}  // namespace corridor::server
