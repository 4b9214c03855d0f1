// Global planning for the daemon: keeps the costmap of the map in use and its zones, rebuilt only when either
// changes, and runs plan requests on the planning executor. Used by the API (POST /api/v1/plan), by the core's goal
// checks and by missions.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "nav/mission/doors.h"
#include "nav/planner/planner.h"
#include "server/runtime/bus.h"
#include "server/runtime/executor.h"
#include "server/runtime/messages.h"

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
  // Takes the map in use (with its zones and doors), the map being explored, and the traffic and obstacle layers from
  // their topics on `planning`, in order with the plans queued there.
  PlannerService(Executor& planning, Bus& bus, const nav::CostmapOptions& options);

  bool has_traffic() const;
  // Thread-safe. The traffic costs plans add now, per cell of the current map (null: none).
  std::shared_ptr<const std::vector<float>> traffic() const;
  // Thread-safe. Bumped by every change of what plans are made on (the map, its zones and doors, the obstacle layer;
  // not traffic): missions check their paths again.
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
  // On the planning executor: plans go on the map being explored while there is one, else on the map in use; a new
  // map takes the layers made for it, if any, and drops the others.
  void Use(std::shared_ptr<const nav::OccupancyGrid> map);
  void OnTraffic(const TrafficLayer& layer);
  void OnObstacles(const ObstacleLayer& layer);

  Executor& planning_;
  Bus& bus_;
  nav::CostmapOptions options_;
  std::shared_ptr<const nav::OccupancyGrid> in_use_;     // planning executor only
  std::shared_ptr<const nav::OccupancyGrid> exploring_;  // planning executor only
  mutable std::mutex mutex_;
  std::shared_ptr<const nav::OccupancyGrid> map_;  // what plans are made on
  std::vector<nav::Zone> zones_;
  std::vector<nav::Door> doors_;
  std::shared_ptr<const std::vector<float>> traffic_;
  std::shared_ptr<const std::vector<std::int8_t>> layer_;
  std::atomic<std::uint64_t> version_{1};
  std::shared_ptr<const nav::Costmap> costmap_;  // planning executor only
  std::uint64_t costmap_version_ = 0;            // planning executor only
};

}  // namespace corridor::server
