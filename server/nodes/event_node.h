// The robot's events, from the EventLog the face node fills: each is recorded in the database (GET /api/v1/events
// reads them there, across restarts) and handed to the webhooks, whose due deliveries it then starts; five times a
// second on the io executor. Each change of a mission's state (mission/changes) is recorded too (GET
// /api/v1/missions). A database error makes the node degraded, never a fault: telling building systems must not stop
// the robot.
#pragma once

#include <cstdint>
#include <functional>

#include "server/api/webhooks.h"
#include "server/runtime/event_log.h"
#include "server/runtime/node.h"
#include "server/store/store.h"

namespace corridor::server {

class EventNode final : public PeriodicNode {
 public:
  static constexpr int kKeptEvents = 10000;  // in the database

  // `webhooks` must live on `io`'s context; it and `store` must outlive the node.
  EventNode(Executor& io, Bus& bus, const EventLog& events, Store& store, Webhooks& webhooks);
  void Activate() override;

 private:
  static constexpr double kRateHz = 5.0;
  void Tick() override;
  // Runs `work` against the database; a failure degrades the node until the next that succeeds.
  void Write(const std::function<void()>& work);

  const EventLog& events_;
  Store& store_;
  Webhooks& webhooks_;
  std::uint64_t read_ = 0;  // the last event handed on
  bool degraded_ = false;
};

}  // namespace corridor::server
