// Going to charge by itself: when the battery runs low (charging.charge_below_percent) an idle robot off its charger
// asks the core for a mission to the dock nearest it, as any other interface would (a refusal is logged). When to go
// is nav's (nav::ChargingPolicy: not again within retry_s, so a docking that failed is tried later, not at once).
#pragma once

#include "nav/mission/docking.h"
#include "server/app/robot_core.h"
#include "server/runtime/node.h"

namespace corridor::server {

class ChargingNode final : public Node {
 public:
  ChargingNode(Executor& executor, Bus& bus, const RobotCore& core, const nav::ChargingOptions& options);
  void Activate() override;

 private:
  void OnBattery(const drivers::BatteryState& battery);

  const RobotCore& core_;
  nav::ChargingPolicy policy_;
};

}  // namespace corridor::server
