#include "server/runtime/node.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "server/runtime/topics.h"

namespace corridor::server {

void LoopStats::Roll(drivers::TimeNs now) const {
  if (now - current_.begin_ns < kWindowNs) return;
  // A window that ended long ago counts as empty.
  previous_ = now - current_.begin_ns < 2 * kWindowNs ? current_ : Window{};
  current_ = Window{.begin_ns = now};
}

void LoopStats::Record(double duration_ms) {
  const drivers::TimeNs now = clock_.Now();
  std::lock_guard lock(mutex_);
  Roll(now);
  ++current_.count;
  current_.total_ms += duration_ms;
  current_.worst_ms = std::max(current_.worst_ms, duration_ms);
  last_ms_ = duration_ms;
  ++loops_;
}

LoopStats::Snapshot LoopStats::snapshot() const {
  const drivers::TimeNs now = clock_.Now();
  std::lock_guard lock(mutex_);
  Roll(now);
  Snapshot s;
  const std::uint64_t count = previous_.count + current_.count;
  const double span_s =
      previous_.count > 0 ? drivers::ToSeconds(now - previous_.begin_ns) : drivers::ToSeconds(now - current_.begin_ns);
  s.rate_hz = span_s > 0.1 ? static_cast<double>(count) / span_s : 0.0;
  s.mean_ms = count > 0 ? (previous_.total_ms + current_.total_ms) / static_cast<double>(count) : 0.0;
  s.worst_ms = std::max(previous_.worst_ms, current_.worst_ms);
  s.last_ms = last_ms_;
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

Node::Node(std::string name, Executor& executor, Bus& bus) : name_(std::move(name)), executor_(executor), bus_(bus) {}

LoopStats& Node::Loop(std::string_view loop) {
  std::lock_guard lock(mutex_);
  auto it = loops_.find(loop);
  if (it == loops_.end())
    it = loops_.emplace(std::string(loop), std::make_unique<LoopStats>(std::string(loop), clock())).first;
  return *it->second;
}

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

bool Node::Run(LoopStats& loop, const std::function<void()>& work) {
  using Wall = std::chrono::steady_clock;
  const Wall::time_point start = Wall::now();
  std::string what;
  try {
    work();
  } catch (const std::exception& e) {
    what = e.what();
    if (what.empty()) what = "an exception without a message";
  } catch (...) {
    what = "an exception that is not a std::exception";
  }
  loop.Record(std::chrono::duration<double, std::milli>(Wall::now() - start).count());
  if (what.empty()) return true;
  const std::string& loop_name = loop.name();
  spdlog::error("{}: {} failed: {}", name_, loop_name, what);
  SetHealth(Health::kError, loop_name + " failed: " + what);
  try {
    bus_.Get(topics::kFaults).Publish(Fault{clock().Now(), name_, loop_name, what});
    OnFault();
  } catch (const std::exception& e) {
    spdlog::critical("{}: handling the fault failed too: {}", name_, e.what());
  }
  return false;
}

nlohmann::json Node::Status() const {
  nlohmann::json loops = nlohmann::json::array();
  double rate_hz = 0.0;
  double total_ms = 0.0;
  double worst_ms = 0.0;
  std::uint64_t count = 0;
  Health health;
  std::string message;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [name, stats] : loops_) {
      const LoopStats::Snapshot s = stats->snapshot();
      loops.push_back({{"name", name},
                       {"rate_hz", s.rate_hz},
                       {"mean_ms", s.mean_ms},
                       {"worst_ms", s.worst_ms},
                       {"last_ms", s.last_ms},
                       {"count", s.loops}});
      rate_hz += s.rate_hz;
      total_ms += s.mean_ms * s.rate_hz;
      worst_ms = std::max(worst_ms, s.worst_ms);
      count += s.loops;
    }
    health = health_;
    message = message_;
  }
  return {{"name", name_},
          {"executor", executor_.name()},
          {"health", ToString(health)},
          {"message", message},
          {"rate_hz", rate_hz},
          {"mean_loop_ms", rate_hz > 0.0 ? total_ms / rate_hz : 0.0},
          {"worst_loop_ms", worst_ms},
          {"loops", count},
          {"callbacks", std::move(loops)}};
}

PeriodicNode::PeriodicNode(std::string name, Executor& executor, Bus& bus, double rate_hz)
    : Node(std::move(name), executor, bus), rate_hz_(rate_hz) {}

void PeriodicNode::Activate() {
  LoopStats& tick = Loop("tick");
  timer_ = std::make_unique<PeriodicTimer>(executor(), std::chrono::nanoseconds(drivers::FromSeconds(1.0 / rate_hz_)),
                                           [this, &tick] { Run(tick, [this] { Tick(); }); });
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
