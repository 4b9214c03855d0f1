#include "server/nodes/charging_node.h"

#include <limits>

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {

ChargingNode::ChargingNode(Executor& executor, Bus& bus, const RobotCore& core, const nav::ChargingOptions& options)
    : Node("charging", executor, bus), core_(core), policy_(options) {}

void ChargingNode::Activate() {
  Subscribe(topics::kBattery, "battery", [this](const auto& battery) { OnBattery(*battery); });
  SetHealth(Health::kOk, "");
}

void ChargingNode::OnBattery(const drivers::BatteryState& battery) {
  const std::shared_ptr<const RobotState> state = core_.State();
  const auto& mission = state->mission;
  const bool busy = mission && nav::InProgress(mission->status);
  const double now_s = drivers::ToSeconds(clock().Now());
  if (!policy_.ShouldGo(now_s, battery.charge, battery.on_charger || state->docked, busy)) return;
  const std::optional<nav::MissionGoal> dock = state->pose ? core_.NearestDock(state->pose->pose) : std::nullopt;
  if (!dock) {
    spdlog::warn("battery at {:.0f} %: no dock on this map to charge at", battery.charge * 100.0);
    return;
  }
  spdlog::info("battery at {:.0f} %: going to charge at '{}'", battery.charge * 100.0, dock->place);
  core_.StartMission({{*dock}, std::numeric_limits<double>::infinity(), "battery"}, [](const MissionResult& result) {
    if (const auto* refusal = std::get_if<nav::MissionRefusal>(&result)) {
      spdlog::warn("battery: the way to the dock is refused: {}", nav::Describe(*refusal, "the dock"));
    }
  });
}

}  // namespace corridor::server
