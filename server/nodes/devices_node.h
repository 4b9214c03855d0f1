// The robot's devices' health (nav/safety/device_health.h), on the io executor: it counts the data each device
// delivers (odometry, scans, frames), asks the native drivers how their links stand, and publishes every device's
// state, rate and last error on devices a few times a second (GET /api/v1/devices, the stream, the console). A device
// is stale after the command gate's timeout for it (safety.*_timeout_s), so the report and the robot agree. The data
// are counted by taps on their topics, on the publishers' threads, not by waking the io thread for every message.
#pragma once

#include <memory>
#include <mutex>
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

  struct Watched {
    DeviceSlot slot;
    nav::DeviceWatch watch;
  };
  // Shared with the taps, which may count a message after the node is gone.
  struct Watches {
    std::mutex mutex;
    std::vector<Watched> devices;
  };
  std::shared_ptr<Watches> watches_ = std::make_shared<Watches>();
};

}  // namespace corridor::server
