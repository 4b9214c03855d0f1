#include "server/nodes/door_node.h"

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {

DoorNode::DoorNode(Executor& io, Bus& bus, std::unique_ptr<DoorController> controller, double poll_s)
    : PeriodicNode("doors", io, bus, 1.0 / poll_s), controller_(std::move(controller)) {}

DoorNode::~DoorNode() { *alive_ = false; }

void DoorNode::Activate() {
  Subscribe(topics::kDoorRequests, "requests",
            [this](const std::shared_ptr<const DoorRequests>& r) { OnRequests(*r); });
  PeriodicNode::Activate();
  SetHealth(Health::kOk, "");
}

void DoorNode::OnRequests(const DoorRequests& requests) {
  for (const nav::DoorRequest& r : requests.requests) {
    if (!r.open) {
      if (asked_.erase(r.door) > 0) {
        spdlog::info("doors: releasing {}", r.door);
        controller_->Release(r.door);
      }
      continue;
    }
    if (asked_.contains(r.door)) continue;
    Asked& asked = asked_[r.door];
    asked.generation = ++generation_;
    asked.in_flight = true;
    spdlog::info("doors: asking {} to open", r.door);
    controller_->Open(r.door,
                      [this, alive = alive_, door = r.door, generation = asked.generation](nav::DoorReport report) {
                        if (!*alive) return;
                        const auto it = asked_.find(door);
                        if (it == asked_.end() || it->second.generation != generation) return;
                        it->second.in_flight = false;
                        Report(door, std::move(report));
                      });
  }
  Publish();
}

void DoorNode::Tick() {
  controller_->Tick();
  for (auto& [door, asked] : asked_) {
    if (asked.in_flight || asked.report.status != nav::DoorStatus::kOpening) continue;
    asked.in_flight = true;
    controller_->State(door, [this, alive = alive_, door = door, generation = asked.generation](nav::DoorReport r) {
      if (!*alive) return;
      const auto it = asked_.find(door);
      if (it == asked_.end() || it->second.generation != generation) return;
      it->second.in_flight = false;
      // A state request that went unanswered is asked again at the next poll; the mission's timeout_s bounds the
      // wait. Only the controller's refusal to open ends it at once.
      if (r.status == nav::DoorStatus::kFailed) {
        spdlog::warn("doors: the state of {}: {}", door, r.detail);
        return;
      }
      Report(door, std::move(r));
    });
  }
}

void DoorNode::Report(const std::string& door, nav::DoorReport report) {
  Asked& asked = asked_.at(door);
  if (asked.report.status == report.status && asked.report.detail == report.detail) return;
  spdlog::info("doors: {} {}{}", door, nav::ToString(report.status), report.detail.empty() ? "" : ": " + report.detail);
  asked.report = std::move(report);
  Publish();
}

void DoorNode::Publish() {
  DoorStates states;
  for (const auto& [door, asked] : asked_) states.doors[door] = asked.report;
  bus().Get(topics::kDoorStates).Publish(std::move(states));
}

}  // namespace corridor::server
