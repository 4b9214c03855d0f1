#include "server/nodes/webhook_node.h"

#include <utility>

namespace corridor::server {

WebhookNode::WebhookNode(Executor& io, Bus& bus, const EventLog& events, Webhooks& webhooks)
    : PeriodicNode("webhooks", io, bus, kRateHz), events_(events), webhooks_(webhooks) {}

void WebhookNode::Tick() {
  try {
    for (const LoggedEvent& event : events_.After(read_)) {
      webhooks_.Publish(event);
      read_ = event.sequence;
    }
    webhooks_.Dispatch();
    if (std::exchange(degraded_, false)) SetHealth(Health::kOk, "");
  } catch (const std::exception& e) {
    degraded_ = true;
    SetHealth(Health::kDegraded, e.what());
  }
}

}  // namespace corridor::server
