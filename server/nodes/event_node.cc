#include "server/nodes/event_node.h"

#include <utility>

#include "server/runtime/topics.h"

namespace corridor::server {

EventNode::EventNode(Executor& io, Bus& bus, const EventLog& events, Store& store, Webhooks& webhooks)
    : PeriodicNode("events", io, bus, kRateHz), events_(events), store_(store), webhooks_(webhooks) {}

void EventNode::Activate() {
  Subscribe(topics::kMissionChanges, "mission",
            [this](const auto& state) { Write([&] { store_.PutMission(state->id, ToJson(*state)); }); });
  PeriodicNode::Activate();
}

void EventNode::Tick() {
  Write([this] {
    for (const LoggedEvent& event : events_.After(read_)) {
      const nlohmann::json document = ToJson(event);
      store_.AddEvent(document, kKeptEvents);
      webhooks_.Publish(document);
      read_ = event.sequence;
    }
    webhooks_.Dispatch();
  });
}

void EventNode::Write(const std::function<void()>& work) {
  try {
    work();
    if (std::exchange(degraded_, false)) SetHealth(Health::kOk, "");
  } catch (const std::exception& e) {
    degraded_ = true;
    SetHealth(Health::kDegraded, e.what());
  }
}

}  // namespace corridor::server
