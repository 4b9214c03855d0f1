// Global planning for the daemon: keeps the costmap of the active map and zones, rebuilt only when either
// changes, and runs plan requests on the planning executor. Used by the API (POST /api/v1/plan) and by missions.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "nav/mission/doors.h"
#include "nav/planner/planner.h"
#include "server/runtime/executor.h"

namespace corridor::server {

struct PlanRequest {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  std::optional<double> goal_yaw;
  std::shared_ptr<std::atomic<bool>> cancel;  // may be null
  bool robot_at_start = false;                // the start is the robot's pose: what is under its footprint is passable
  // Obstacles the map does not show, to go round where there is room (nav::LocalNavigator::Blocking): each adds
  // blocking_cost to the cells within blocking_radius_m of it (nav::AddPointCost).
  std::vector<Eigen::Vector2d> blocking;
  double blocking_radius_m = 0.0;
  float blocking_cost = 0.0f;
};

struct PlanReply {
  nav::PlanResult result;
  std::uint64_t version = 0;                    // of the map and zones it was planned on
  double planning_ms = 0.0;                     // search and path processing
  double costmap_ms = 0.0;                      // 0 when the cached costmap was used
  std::shared_ptr<const nav::Costmap> costmap;  // what it was planned on
};

class PlannerService {
 public:
  PlannerService(Executor& planning, const nav::CostmapOptions& options);

  // Thread-safe. Each change bumps the version; the costmap is rebuilt on the next request.
  void SetMap(std::shared_ptr<const nav::OccupancyGrid> map);
  void SetZones(std::vector<nav::Zone> zones);
  // The doors of the current map: what the obstacle layer has on their lines (a closed panel) is not planned round.
  void SetDoors(std::vector<nav::Door> doors);
  // Thread-safe. Where people have been walking, per cell of `map` (nav::TrafficMap::StepCost): added to every
  // plan's step costs from now on, when `map` is the current map; a cost made for a map since replaced is dropped.
  // Does not change the version (it is not the map). Null: none (nobody has walked): missions do not reroute.
  void SetTraffic(std::shared_ptr<const std::vector<float>> cost, const nav::OccupancyGrid* map);
  bool has_traffic() const;
  // Thread-safe. Obstacles the map does not show (the 3D map's layer), per cell of `map`: occupied cells of the layer
  // are obstacles in every costmap from now on, when `map` is the current map. Bumps the version (missions check
  // their paths). Null: none.
  void SetObstacleLayer(std::shared_ptr<const std::vector<std::int8_t>> cells, const nav::OccupancyGrid* map);
  // Thread-safe. The traffic costs plans add now, per cell of the current map (null: none).
  std::shared_ptr<const std::vector<float>> traffic() const;
  std::uint64_t version() const { return version_.load(); }
  const nav::CostmapOptions& options() const { return options_; }

  // Queues a plan on the planning executor; `done` runs there.
  void Plan(PlanRequest request, std::function<void(PlanReply)> done);
  // Queues `work` with the current costmap on the planning executor (for checks such as "is the rest of my path
  // still free?").
  void WithCostmap(std::function<void(std::shared_ptr<const nav::Costmap>, std::uint64_t version)> work);

 private:
  // On the planning executor: the costmap for the current map and zones, and how long building it took.
  std::shared_ptr<const nav::Costmap> Current(double* build_ms);

  Executor& planning_;
  nav::CostmapOptions options_;
  mutable std::mutex mutex_;
  std::shared_ptr<const nav::OccupancyGrid> map_;
  std::vector<nav::Zone> zones_;
  std::vector<nav::Door> doors_;
  std::shared_ptr<const std::vector<float>> traffic_;
  std::shared_ptr<const std::vector<std::int8_t>> layer_;
  std::atomic<std::uint64_t> version_{1};
  std::shared_ptr<const nav::Costmap> costmap_;  // planning executor only
  std::uint64_t costmap_version_ = 0;            // planning executor only
};

}  // namespace corridor::server
