// The map and what is drawn on it: the active map and its image, editing it cell by cell or by a new image, choosing
// another; the building, zones, places, doors and lift stops; the 3D map and the traffic layer.
#pragma once

#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/nodes/octree_node.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/executor.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

class MapApi {
 public:
  // `octree`: null when the 3D map is off. `simulated`: the simulator's doors are on its world's map. `io`: where
  // the store is written, as every handler does.
  MapApi(Bus& bus, const RobotCore& core, const Config& config, MapLibrary& maps, Store& store, PlannerService& planner,
         OctreeNode* octree, bool simulated, Executor& io);
  void AddRoutes(Router& routes) const;

 private:
  Bus& bus_;
  const RobotCore& core_;
  const Config& config_;
  MapLibrary& maps_;
  Store& store_;
  PlannerService& planner_;
  OctreeNode* octree_;
  bool simulated_;
  Executor& io_;
};

}  // namespace corridor::server
