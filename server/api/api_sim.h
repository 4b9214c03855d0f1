// The simulator's own routes, under /api/v1/sim/: fault injection (a camera that stops, a stalled control loop), the
// robot kidnapped to a pose, and the doors and lifts a building's controllers drive. Each answers 404 without the
// simulator.
#pragma once

#include <atomic>
#include <memory>

#include "drivers/sim/sim_robot.h"
#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/runtime/executor.h"

namespace corridor::server {

class SimulatorApi {
 public:
  // `sim`: null with real drivers. `control`: the control executor, which the stalled-loop fault blocks.
  SimulatorApi(drivers::sim::SimRobot* sim, const RobotCore& core, Executor& control);
  void AddRoutes(Router& routes) const;

 private:
  void AddFaultRoutes(Router& routes) const;
  void AddDoorRoutes(Router& routes) const;
  void AddLiftRoutes(Router& routes) const;
  // The simulated robot, or ApiError 404.
  drivers::sim::SimRobot& Sim() const;

  drivers::sim::SimRobot* sim_;
  const RobotCore& core_;
  Executor& control_;
  std::shared_ptr<std::atomic<bool>> control_stalled_ = std::make_shared<std::atomic<bool>>(false);
};

}  // namespace corridor::server
