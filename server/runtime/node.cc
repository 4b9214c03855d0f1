#include "server/runtime/node.h"

#include <spdlog/spdlog.h>

namespace corridor::server {

void LoopStats::Roll(drivers::TimeNs now) const {
  if (now - current_.begin_ns < kWindowNs) return;
  // A window that ended long ago counts as empty.
  previous_ = now - current_.begin_ns < 2 * kWindowNs ? current_ : Window{};
  current_ = Window{.begin_ns = now};
}

void LoopStats::Record(drivers::TimeNs start_ns) {
  const drivers::TimeNs now = clock_.Now();
  const double ms = static_cast<double>(now - start_ns) * 1e-6;
  std::lock_guard lock(mutex_);
  Roll(now);
  ++current_.count;
  current_.total_ms += ms;
  current_.worst_ms = std::max(current_.worst_ms, ms);
  ++loops_;
}

LoopStats::Snapshot LoopStats::snapshot() const {
  const drivers::TimeNs now = clock_.Now();
  std::lock_guard lock(mutex_);
  Roll(now);
  Snapshot s;
  const std::uint64_t count = previous_.count + current_.count;
  const double span_s = previous_.count > 0 ? drivers::ToSeconds(now - previous_.begin_ns)
                                            : drivers::ToSeconds(now - current_.begin_ns);
  s.rate_hz = span_s > 0.1 ? static_cast<double>(count) / span_s : 0.0;
  s.mean_ms = count > 0 ? (previous_.total_ms + current_.total_ms) / static_cast<double>(count) : 0.0;
  s.worst_ms = std::max(previous_.worst_ms, current_.worst_ms);
  s.loops = loops_;
  return s;
}

const char* ToString(Health health) {
  switch (health) {
    case Health::kOk: return "ok";
    case Health::kDegraded: return "degraded";
    case Health::kError: return "error";
    case Health::kInactive: return "inactive";
  }
  return "unknown";
}

Node::Node(std::string name, std::string executor, const drivers::Clock& clock)
    : name_(std::move(name)), executor_(std::move(executor)), clock_(clock), stats_(clock) {}

void Node::SetHealth(Health health, std::string message) {
  std::lock_guard lock(mutex_);
  if (health != health_ || message != message_) {
    if (health == Health::kError) {
      spdlog::warn("{}: {}", name_, message);
    } else {
      spdlog::info("{}: {}{}{}", name_, ToString(health), message.empty() ? "" : ": ", message);
    }
  }
  health_ = health;
  message_ = std::move(message);
}

nlohmann::json Node::Status() const {
  const LoopStats::Snapshot s = stats_.snapshot();
  std::lock_guard lock(mutex_);
  return {{"name", name_},
          {"executor", executor_},
          {"health", ToString(health_)},
          {"message", message_},
          {"rate_hz", s.rate_hz},
          {"mean_loop_ms", s.mean_ms},
          {"worst_loop_ms", s.worst_ms},
          {"loops", s.loops}};
}

PeriodicNode::PeriodicNode(std::string name, Executor& executor, const drivers::Clock& clock, double rate_hz)
    : Node(std::move(name), executor.name(), clock), executor_(executor), rate_hz_(rate_hz) {}

void PeriodicNode::Activate() {
  timer_ = std::make_unique<PeriodicTimer>(executor_, std::chrono::nanoseconds(drivers::FromSeconds(1.0 / rate_hz_)),
                                           [this] {
                                             LoopTimer timer(stats(), clock());
                                             Tick();
                                           });
  SetHealth(Health::kOk, "");
}

void PeriodicNode::Deactivate() {
  if (timer_) timer_->Stop();
  SetHealth(Health::kInactive, "");
}

void Lifecycle::ConfigureAll() {
  for (auto& n : nodes_) n->Configure();
}

void Lifecycle::ActivateAll() {
  for (auto& n : nodes_) n->Activate();
}

void Lifecycle::DeactivateAll() {
  for (auto it = nodes_.rbegin(); it != nodes_.rend(); ++it) (*it)->Deactivate();
}

void Lifecycle::CleanupAll() {
  for (auto it = nodes_.rbegin(); it != nodes_.rend(); ++it) (*it)->Cleanup();
}

}  // namespace corridor::server
