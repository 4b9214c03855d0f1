#include "server/nodes/planner_service.h"

#include <chrono>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// Around a door's line, what the camera mapped is the panel (and its frame), not an obstacle.
constexpr double kDoorHalfWidthM = 0.1;

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

PlannerService::PlannerService(Executor& planning, Bus& bus, const nav::CostmapOptions& options)
    : planning_(planning), bus_(bus), options_(options) {
  bus.Get(topics::kMapInUse).Subscribe(planning, [this](const std::shared_ptr<const MapInUse>& map) {
    {
      std::lock_guard lock(mutex_);
      zones_ = map->zones;
      doors_ = map->doors;
      ++version_;
    }
    in_use_ = map->grid;
    Use(exploring_ ? exploring_ : in_use_);
  });
  bus.Get(topics::kExploringMap).Subscribe(planning, [this](const std::shared_ptr<const ExploringMap>& map) {
    exploring_ = map->grid;
    Use(exploring_ ? exploring_ : in_use_);
  });
  bus.Get(topics::kTrafficLayer).Subscribe(planning, [this](const auto& layer) { OnTraffic(*layer); });
  bus.Get(topics::kObstacleLayer).Subscribe(planning, [this](const auto& layer) { OnObstacles(*layer); });
}

void PlannerService::Use(std::shared_ptr<const nav::OccupancyGrid> map) {
  {
    std::lock_guard lock(mutex_);
    if (map == map_) return;
    map_ = std::move(map);
    traffic_ = nullptr;
    layer_ = nullptr;
    ++version_;
  }
  if (const auto traffic = bus_.Get(topics::kTrafficLayer).latest()) OnTraffic(*traffic);
  if (const auto layer = bus_.Get(topics::kObstacleLayer).latest()) OnObstacles(*layer);
}

void PlannerService::OnTraffic(const TrafficLayer& layer) {
  std::lock_guard lock(mutex_);
  if (layer.map != map_) return;  // made for another map (the tracker had not yet heard of this one)
  traffic_ = layer.cost;
}

void PlannerService::OnObstacles(const ObstacleLayer& layer) {
  std::lock_guard lock(mutex_);
  if (layer.map != map_) return;  // made for a map since replaced
  layer_ = layer.cells;
  ++version_;
}

bool PlannerService::has_traffic() const { return traffic() != nullptr; }

std::shared_ptr<const std::vector<float>> PlannerService::traffic() const {
  std::lock_guard lock(mutex_);
  return traffic_;
}

std::shared_ptr<const nav::Costmap> PlannerService::Current(double* build_ms) {
  *build_ms = 0.0;
  std::shared_ptr<const nav::OccupancyGrid> map;
  std::shared_ptr<const std::vector<std::int8_t>> layer;
  std::vector<nav::Zone> zones;
  std::vector<nav::Door> doors;
  std::uint64_t version = 0;
  {
    std::lock_guard lock(mutex_);
    version = version_.load();
    if (costmap_ && costmap_version_ == version) return costmap_;
    map = map_;
    layer = layer_;
    zones = zones_;
    doors = doors_;
  }
  const auto start = std::chrono::steady_clock::now();
  if (layer && !doors.empty()) {
    auto cleared = std::make_shared<std::vector<std::int8_t>>(*layer);
    nav::ClearDoors(*map, doors, kDoorHalfWidthM, *cleared);
    layer = std::move(cleared);
  }
  costmap_ = layer ? std::make_shared<const nav::Costmap>(*map, *layer, zones, options_)
                   : std::make_shared<const nav::Costmap>(*map, zones, options_);
  costmap_version_ = version;
  *build_ms = MsSince(start);
  return costmap_;
}

void PlannerService::Plan(PlanRequest request, std::function<void(PlanReply)> done) {
  planning_.Post([this, request = std::move(request), done = std::move(done)] {
    PlanReply reply;
    const auto costmap = Current(&reply.costmap_ms);
    reply.version = costmap_version_;
    std::shared_ptr<const std::vector<float>> traffic;
    {
      std::lock_guard lock(mutex_);
      traffic = traffic_;
    }
    const std::vector<float> extra =
        nav::ExtraCosts(*costmap, traffic ? std::span<const float>(*traffic) : std::span<const float>(),
                        request.blocking, request.blocking_radius_m, request.blocking_cost);
    nav::PathOptions path_options;
    path_options.extra_cost = extra;
    path_options.robot_at_start = request.robot_at_start;
    const auto start = std::chrono::steady_clock::now();
    reply.result =
        nav::PlanPath(*costmap, request.start, request.goal, request.goal_yaw, request.cancel.get(), path_options);
    reply.planning_ms = MsSince(start);
    reply.costmap = costmap;
    done(std::move(reply));
  });
}

void PlannerService::WithCostmap(std::function<void(std::shared_ptr<const nav::Costmap>, std::uint64_t)> work) {
  planning_.Post([this, work = std::move(work)] {
    double build_ms = 0.0;
    work(Current(&build_ms), costmap_version_);
  });
}

}  // namespace corridor::server
