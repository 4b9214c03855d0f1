// Runs the simulator in real time on the sim executor: each tick steps the simulated robot until simulated time
// catches up with wall time. The SimRobot's sensors publish through the driver bridge as real devices would.
#pragma once

#include "drivers/sim/sim_robot.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class SimNode final : public PeriodicNode {
 public:
  SimNode(Executor& executor, Bus& bus, drivers::sim::SimRobot& robot, const drivers::Clock& wall_clock);
  void Activate() override;

 private:
  void Tick() override;
  void PublishPedestrians();

  Bus& bus_;
  drivers::sim::SimRobot& robot_;
  drivers::TimeNs wall_start_ns_ = 0;
  drivers::TimeNs sim_start_ns_ = 0;
  bool has_pedestrians_ = false;
};

}  // namespace corridor::server
