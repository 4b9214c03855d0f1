// Tracks moving objects from the 2D laser (nav/tracking/moving_objects.h): each scan is put in the map frame with the
// newest pose estimate and added to the tracker, whose objects and static points go out on tracking/objects for the
// mission's evasion and the console. On the mapping executor, off the camera's control path. Walls of the active
// map are not objects: the map library hands each new map to SetMap.
#pragma once

#include <memory>

#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"
#include "nav/tracking/moving_objects.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class TrackingNode final : public Node {
 public:
  // `base_T_laser`: the laser's pose on the robot. Throws std::invalid_argument for bad options.
  TrackingNode(Executor& mapping, Bus& bus, const drivers::Clock& clock, const nav::Pose2& base_T_laser,
               const nav::MovingObjectOptions& options);
  void Activate() override;
  // Thread-safe: takes effect on the node's executor.
  void SetMap(std::shared_ptr<const nav::OccupancyGrid> map);

 private:
  void OnScan(const drivers::LaserScan& scan);

  Executor& executor_;
  Bus& bus_;
  nav::Pose2 base_T_laser_;
  nav::MovingObjectTracker tracker_;
};

}  // namespace corridor::server
