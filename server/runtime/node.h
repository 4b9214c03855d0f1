// Nodes: thin runtime wrappers around algorithm cores (subscribe, call the core, publish). Each keeps a loop-time
// counter and a health status that /api/v1/state reports, and follows one lifecycle:
// Configure -> Activate -> (running) -> Deactivate -> Cleanup.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "drivers/clock.h"
#include "server/runtime/executor.h"

namespace corridor::server {

// Loop rate and loop times over a sliding window of about two seconds. Thread-safe.
class LoopStats {
 public:
  struct Snapshot {
    double rate_hz = 0.0;
    double mean_ms = 0.0;
    double worst_ms = 0.0;         // over the window
    std::uint64_t loops = 0;       // since start
  };

  explicit LoopStats(const drivers::Clock& clock) : clock_(clock) {}
  // One loop that started at start_ns and ended now.
  void Record(drivers::TimeNs start_ns);
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

  const drivers::Clock& clock_;
  mutable std::mutex mutex_;
  mutable Window current_;
  mutable Window previous_;
  std::uint64_t loops_ = 0;
};

enum class Health { kOk, kDegraded, kError, kInactive };
const char* ToString(Health health);

// Measures one loop into `stats` from construction to destruction.
class LoopTimer {
 public:
  explicit LoopTimer(LoopStats& stats, const drivers::Clock& clock) : stats_(stats), start_(clock.Now()) {}
  ~LoopTimer() { stats_.Record(start_); }
  LoopTimer(const LoopTimer&) = delete;
  LoopTimer& operator=(const LoopTimer&) = delete;

 private:
  LoopStats& stats_;
  drivers::TimeNs start_;
};

class Node {
 public:
  // `clock` measures loop times (wall time, even in simulation: loop times are about this computer).
  Node(std::string name, std::string executor, const drivers::Clock& clock);
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  virtual ~Node() = default;

  virtual void Configure() {}
  virtual void Activate() {}
  virtual void Deactivate() {}
  virtual void Cleanup() {}

  const std::string& name() const { return name_; }
  const std::string& executor() const { return executor_; }
  LoopStats& stats() { return stats_; }
  // Health, its message, and the loop statistics, for /api/v1/state. Thread-safe.
  nlohmann::json Status() const;

 protected:
  // Thread-safe.
  void SetHealth(Health health, std::string message);
  const drivers::Clock& clock() const { return clock_; }

 private:
  std::string name_;
  std::string executor_;
  const drivers::Clock& clock_;
  LoopStats stats_;
  mutable std::mutex mutex_;
  Health health_ = Health::kInactive;
  std::string message_;
};

// A node driven by a period: Tick() runs on its executor at rate_hz, measured into stats(), from Activate() until
// Deactivate(). Subclasses that override these call the base versions.
class PeriodicNode : public Node {
 public:
  PeriodicNode(std::string name, Executor& executor, const drivers::Clock& clock, double rate_hz);
  void Activate() override;
  void Deactivate() override;

 protected:
  virtual void Tick() = 0;
  Executor& executor() { return executor_; }

 private:
  Executor& executor_;
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
