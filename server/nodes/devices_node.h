// The robot's devices' health (nav/safety/device_health.h), on the io executor: it counts the data each device
// delivers (odometry, scans, frames), asks the native drivers how their links stand, and publishes every device's
// state, rate and last error on devices a few times a second (GET /api/v1/devices, the stream, the console). A device
// is stale after the command gate's timeout for it (safety.*_timeout_s), so the report and the robot agree.
#pragma once

#include <vector>

#include "nav/safety/command_gate.h"
#include "nav/safety/device_health.h"
#include "server/nodes/driver_bridge.h"
#include "server/runtime/node.h"

namespace corridor::server {

class DevicesNode final : public PeriodicNode {
 public:
  DevicesNode(Executor& io, Bus& bus, std::vector<DeviceSlot> slots, const nav::CommandGateOptions& safety);
  void Activate() override;

 private:
  void Tick() override;
  void Arrived(nav::Device device);

  struct Watched {
    DeviceSlot slot;
    nav::DeviceWatch watch;
  };
  std::vector<Watched> devices_;
};

}  // namespace corridor::server
