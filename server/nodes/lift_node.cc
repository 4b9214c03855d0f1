#include "server/nodes/lift_node.h"

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {

LiftNode::LiftNode(Executor& io, Bus& bus, std::unique_ptr<LiftController> controller, double poll_s)
    : PeriodicNode("lifts", io, bus, 1.0 / poll_s), controller_(std::move(controller)) {}

LiftNode::~LiftNode() { *alive_ = false; }

void LiftNode::Activate() {
  Subscribe(topics::kLiftRequests, "requests",
            [this](const std::shared_ptr<const LiftRequests>& r) { OnRequests(*r); });
  PeriodicNode::Activate();
  SetHealth(Health::kOk, "");
}

void LiftNode::OnRequests(const LiftRequests& requests) {
  for (const nav::LiftRequest& r : requests.requests) {
    if (r.release) {
      if (lifts_.erase(r.lift) > 0) {
        spdlog::info("lifts: releasing {}", r.lift);
        controller_->Release(r.lift);
      }
      continue;
    }
    InUse& lift = lifts_[r.lift];
    lift.floor = r.floor;
    lift.generation = ++generation_;
    lift.call_pending = true;
    lift.in_flight = false;
    Call(r.lift);
  }
  Publish();
}

void LiftNode::Call(const std::string& id) {
  InUse& lift = lifts_.at(id);
  lift.call_pending = false;
  lift.in_flight = true;
  spdlog::info("lifts: calling {} to floor {}", id, lift.floor);
  controller_->Call(id, lift.floor, [this, alive = alive_, id, generation = lift.generation](nav::LiftReport r) {
    if (!*alive) return;
    const auto it = lifts_.find(id);
    if (it == lifts_.end() || it->second.generation != generation) return;
    it->second.in_flight = false;
    if (r.failed) {
      spdlog::warn("lifts: calling {}: {}; calling again", id, r.detail);
      it->second.call_pending = true;
      return;
    }
    if (r.refused) Report(id, std::move(r));
  });
}

void LiftNode::Tick() {
  controller_->Tick();
  for (auto& [id, lift] : lifts_) {
    if (lift.in_flight) continue;
    if (lift.call_pending) {
      Call(id);
      continue;
    }
    if (lift.report.refused) continue;
    lift.in_flight = true;
    controller_->State(id, [this, alive = alive_, id = id, generation = lift.generation](nav::LiftReport r) {
      if (!*alive) return;
      const auto it = lifts_.find(id);
      if (it == lifts_.end() || it->second.generation != generation) return;
      it->second.in_flight = false;
      // A state request that went unanswered is asked again at the next poll; the ride's timeouts bound the wait.
      if (r.failed) {
        spdlog::warn("lifts: the state of {}: {}", id, r.detail);
        return;
      }
      Report(id, std::move(r));
    });
  }
}

void LiftNode::Report(const std::string& id, nav::LiftReport report) {
  InUse& lift = lifts_.at(id);
  const nav::LiftReport& old = lift.report;
  if (old.floor == report.floor && old.door_open == report.door_open && old.refused == report.refused &&
      old.detail == report.detail) {
    return;
  }
  if (report.refused) {
    spdlog::warn("lifts: {} refused: {}", id, report.detail);
  } else {
    spdlog::info("lifts: {} at floor {}, door {}", id, report.floor, report.door_open ? "open" : "closed");
  }
  lift.report = std::move(report);
  Publish();
}

void LiftNode::Publish() {
  LiftStates states;
  for (const auto& [id, lift] : lifts_) states.lifts[id] = lift.report;
  bus().Get(topics::kLiftStates).Publish(std::move(states));
}

}  // namespace corridor::server
