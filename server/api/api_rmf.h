// Open-RMF fleet adapters (server/fleet/rmf.h) under /api/v1/rmf/: the calls of the fleet adapter template's
// RobotClientAPI, one route each, and the robot's state as Open-RMF's robot_state.
#pragma once

#include <memory>
#include <string>

#include "server/api/api_navigation.h"
#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/fleet/rmf.h"
#include "server/runtime/bus.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

class RmfApi {
 public:
  // `robot_name`: the robot's name in robot_state.
  RmfApi(Bus& bus, const RobotCore& core, const MapLibrary& maps, const Store& store, const BuildingOptions& building,
         const MissionRequests& missions, std::string robot_name);
  void AddRoutes(Router& routes) const;

 private:
  // The Open-RMF robot state's inputs, from the core's state now.
  RmfSample Sample() const;

  Bus& bus_;
  const RobotCore& core_;
  const MapLibrary& maps_;
  const Store& store_;
  const BuildingOptions& building_;
  const MissionRequests& missions_;
  std::string robot_name_;
  std::shared_ptr<RmfCommands> commands_ = std::make_shared<RmfCommands>();
};

}  // namespace corridor::server
