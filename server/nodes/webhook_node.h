// Hands the robot's events (the EventLog the face node fills) to the webhooks, and starts the deliveries that are due,
// five times a second on the io executor. A database error makes the node degraded, never a fault: a building
// system's webhook must not stop the robot.
#pragma once

#include <cstdint>

#include "server/api/webhooks.h"
#include "server/runtime/event_log.h"
#include "server/runtime/node.h"

namespace corridor::server {

class WebhookNode final : public PeriodicNode {
 public:
  // `webhooks` must live on `io`'s context and outlive the node.
  WebhookNode(Executor& io, Bus& bus, const EventLog& events, Webhooks& webhooks);

 private:
  static constexpr double kRateHz = 5.0;
  void Tick() override;

  const EventLog& events_;
  Webhooks& webhooks_;
  std::uint64_t read_ = 0;  // the last event handed on
  bool degraded_ = false;
};

}  // namespace corridor::server
