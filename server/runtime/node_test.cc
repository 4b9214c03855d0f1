#include "server/runtime/node.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// A node whose odometry handler fails on a pressed bumper, as a node with a bug would on input it did not foresee.
class FragileNode final : public Node {
 public:
  FragileNode(Executor& executor, Bus& bus) : Node("fragile", executor, bus) {}
  void Activate() override {
    Subscribe(topics::kOdometry, "odometry", [this](const auto& odometry) {
      if (odometry->bumper_pressed) throw std::out_of_range("no such wheel");
      ++handled;
    });
    SetHealth(Health::kOk, "");
  }
  void OnFault() override { ++faults; }
  int handled = 0;
  int faults = 0;
};

TEST(NodeTest, AFailingCallbackIsLoggedPublishedAsAFaultAndTheNodeGoesOn) {
  drivers::ManualClock clock;
  Executors executors(clock, Schedule::kLockstep);
  Bus bus;
  FragileNode node(executors.control, bus);
  node.Activate();
  bus.Get(topics::kOdometry).Publish(drivers::WheelOdometry{0, {}, {}, true});
  executors.RunUntilIdle();
  const nlohmann::json status = node.Status();
  EXPECT_EQ(status["health"], "error");
  EXPECT_EQ(status["message"], "odometry failed: no such wheel");
  const auto fault = bus.Get(topics::kFaults).latest();
  ASSERT_NE(fault, nullptr);
  EXPECT_EQ(fault->node, "fragile");
  EXPECT_EQ(fault->loop, "odometry");
  EXPECT_EQ(fault->what, "no such wheel");
  EXPECT_EQ(node.faults, 1);
  EXPECT_EQ(executors.control.escaped(), 0u) << "the node caught it, not the executor";
  // The next message is handled as usual.
  bus.Get(topics::kOdometry).Publish(drivers::WheelOdometry{1, {}, {}, false});
  executors.RunUntilIdle();
  EXPECT_EQ(node.handled, 1);
}

TEST(NodeTest, EachCallbackIsTimedInItsOwnLoopCounter) {
  drivers::ManualClock clock;
  Executors executors(clock, Schedule::kLockstep);
  Bus bus;
  FragileNode node(executors.control, bus);
  node.Activate();
  for (int i = 1; i <= 40; ++i) {
    clock.Set(drivers::FromSeconds(0.05 * i));
    bus.Get(topics::kOdometry).Publish(drivers::WheelOdometry{clock.Now(), {}, {}, false});
    executors.RunUntilIdle();
  }
  const nlohmann::json status = node.Status();
  ASSERT_EQ(status["callbacks"].size(), 1u);
  const nlohmann::json& odometry = status["callbacks"][0];
  EXPECT_EQ(odometry["name"], "odometry");
  EXPECT_EQ(odometry["count"], 40);
  EXPECT_NEAR(odometry["rate_hz"].get<double>(), 20.0, 1.0);  // per second of the graph's clock
  EXPECT_EQ(status["loops"], 40);
  EXPECT_GE(odometry["worst_ms"].get<double>(), odometry["mean_ms"].get<double>());
}

}  // namespace
}  // namespace corridor::server
