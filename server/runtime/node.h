// Nodes: thin runtime wrappers around algorithm cores (subscribe, call the core, publish). Each follows one lifecycle
// (Configure -> Activate -> running -> Deactivate -> Cleanup), reports a health status, and times every callback it
// owns in a named loop counter (a depth frame's MORP, the navigator's decision, a timer tick), which /api/v1/state
// shows.
//
// A node's callbacks never take the daemon down. One that throws is logged with the node's and the loop's names, the
// node's health turns to error, and a Fault goes out on safety/faults: the control node holds the robot in a
// protective stop (nav/safety/command_gate.h). The node's next callbacks run as usual.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/clock.h"
#include "server/runtime/bus.h"
#include "server/runtime/executor.h"

namespace corridor::server {

// Loop rate and loop times over a sliding window of about two seconds. The window and the rate are on the graph's
// clock (frames per simulated second in lockstep); durations are wall time on this computer. Thread-safe.
class LoopStats {
 public:
  struct Snapshot {
    double rate_hz = 0.0;
    double mean_ms = 0.0;
    double worst_ms = 0.0;    // over the window
    double last_ms = 0.0;     // the latest loop's
    std::uint64_t loops = 0;  // since start
  };

  LoopStats(std::string name, const drivers::Clock& clock) : name_(std::move(name)), clock_(clock) {}
  const std::string& name() const { return name_; }
  // One loop that ended now on the graph's clock and took `duration_ms` of wall time.
  void Record(double duration_ms);
  Snapshot snapshot() const;

 private:
  static constexpr drivers::TimeNs kWindowNs = 2 * drivers::kNsPerSecond;
  struct Window {
    drivers::TimeNs begin_ns = 0;
    std::uint64_t count = 0;
    double total_ms = 0.0;
    double worst_ms = 0.0;
  };
  void Roll(drivers::TimeNs now) const;

  const std::string name_;
  const drivers::Clock& clock_;
  mutable std::mutex mutex_;
  mutable Window current_;
  mutable Window previous_;
  std::uint64_t loops_ = 0;
  double last_ms_ = 0.0;
};

enum class Health { kOk, kDegraded, kError, kInactive };
const char* ToString(Health health);

class Node {
 public:
  Node(std::string name, Executor& executor, Bus& bus);
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  virtual ~Node() = default;

  virtual void Configure() {}
  virtual void Activate() {}
  virtual void Deactivate() {}
  virtual void Cleanup() {}

  const std::string& name() const { return name_; }
  // Health, its message, and the loop counters (all together, and each by name), for /api/v1/state. Thread-safe.
  nlohmann::json Status() const;
  // The loop counter named `loop`, created on first use. Thread-safe; the reference stays valid.
  LoopStats& Loop(std::string_view loop);

 protected:
  // Thread-safe.
  void SetHealth(Health health, std::string message);
  const drivers::Clock& clock() const { return executor_.clock(); }
  Executor& executor() { return executor_; }
  Bus& bus() { return bus_; }

  // Runs `work` as one pass of `loop`: timed, and guarded (see the top of this file). Returns false if it threw.
  bool Run(LoopStats& loop, const std::function<void()>& work);
  bool Run(std::string_view loop, const std::function<void()>& work) { return Run(Loop(loop), work); }
  // Delivers `topic`'s messages to `handler(const std::shared_ptr<const T>&)` on this node's executor, each as one
  // pass of `loop`.
  template <typename T, typename F>
  void Subscribe(TopicName<T> topic, std::string_view loop, F handler) {
    LoopStats& stats = Loop(loop);
    bus_.Get(topic).Subscribe(executor_,
                              [this, &stats, handler = std::move(handler)](const std::shared_ptr<const T>& message) {
                                Run(stats, [&] { handler(message); });
                              });
  }
  // Called on the node's executor after one of its callbacks threw, once the fault is published.
  virtual void OnFault() {}

 private:
  std::string name_;
  Executor& executor_;
  Bus& bus_;
  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<LoopStats>, std::less<>> loops_;
  Health health_ = Health::kInactive;
  std::string message_;
};

// A node driven by a period: Tick() runs on its executor at rate_hz of the executor's clock, as the loop "tick",
// from Activate() until Deactivate(). Subclasses that override these call the base versions.
class PeriodicNode : public Node {
 public:
  PeriodicNode(std::string name, Executor& executor, Bus& bus, double rate_hz);
  void Activate() override;
  void Deactivate() override;

 protected:
  virtual void Tick() = 0;

 private:
  double rate_hz_;
  std::unique_ptr<PeriodicTimer> timer_;
};

// Owns the nodes; brings them up in the order added and down in reverse order.
class Lifecycle {
 public:
  void Add(std::unique_ptr<Node> node) { nodes_.push_back(std::move(node)); }
  void ConfigureAll();
  void ActivateAll();
  void DeactivateAll();
  void CleanupAll();
  const std::vector<std::unique_ptr<Node>>& nodes() const { return nodes_; }

 private:
  std::vector<std::unique_ptr<Node>> nodes_;
};

}  // namespace corridor::server
