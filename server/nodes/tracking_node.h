// Tracks moving objects from the 2D laser (nav/tracking/moving_objects.h): each scan is put in the map frame with the
// newest pose estimate and added to the tracker, whose objects and static points go out on tracking/objects for the
// mission's evasion and the console. On the mapping executor, off the camera's control path. Walls of the active
// map are not objects: the map library hands each new map to SetMap. The tracks also mark where people walk
// (nav/tracking/traffic_map.h); every second the costs of those ways go to `on_traffic`, for the planner.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"
#include "nav/tracking/moving_objects.h"
#include "nav/tracking/traffic_map.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

// Where people walk, per cell of `map` (the map the costs were made over): for PlannerService::SetTraffic.
using TrafficCallback =
    std::function<void(std::shared_ptr<const std::vector<float>> cost, const nav::OccupancyGrid* map)>;

class TrackingNode final : public Node {
 public:
  // `base_T_laser`: the laser's pose on the robot. Throws std::invalid_argument for bad options.
  // `on_traffic` (may be empty) is called on the node's executor; with traffic.weight 0 it is never called.
  TrackingNode(Executor& mapping, Bus& bus, const drivers::Clock& clock, const nav::Pose2& base_T_laser,
               const nav::MovingObjectOptions& options, const nav::TrafficOptions& traffic,
               TrafficCallback on_traffic);
  void Activate() override;
  // Thread-safe: takes effect on the node's executor.
  void SetMap(std::shared_ptr<const nav::OccupancyGrid> map);

 private:
  void OnScan(const drivers::LaserScan& scan);

  Executor& executor_;
  Bus& bus_;
  nav::Pose2 base_T_laser_;
  nav::MovingObjectTracker tracker_;
  nav::TrafficOptions traffic_options_;
  TrafficCallback on_traffic_;
  std::optional<nav::TrafficMap> traffic_;  // over the current map
  std::shared_ptr<const nav::OccupancyGrid> map_;  // the current map
  double traffic_sent_s_ = -std::numeric_limits<double>::infinity();  // scan time of the last costs handed on
};

}  // namespace corridor::server
