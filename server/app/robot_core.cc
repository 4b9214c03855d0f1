#include "server/app/robot_core.h"

#include <cstdio>
#include <memory>
#include <numbers>

#include <spdlog/spdlog.h>

#include "server/runtime/demand.h"

namespace corridor::server {

nav::Building CurrentBuilding(const Config& config, const Store& store) {
  nav::Building building = BuildingOf(config.building);
  for (auto& [lift, stop] : store.LiftStops()) nav::PutStop(building, lift, std::move(stop));
  return building;
}

RobotCore::RobotCore(const Config& config, PlannerService& planner, MissionNode& missions,
                     LocalizationNode& localization, const MapLibrary& maps, const Store& store)
    : config_(config), planner_(planner), missions_(missions), localization_(localization), maps_(maps),
      store_(store) {}

void RobotCore::StartMission(MissionOrder order, std::function<void(MissionResult)> done) const {
  DEMAND(!order.goals.empty());
  planner_.WithCostmap([this, order = std::move(order), done = std::move(done)](
                           std::shared_ptr<const nav::Costmap> costmap, std::uint64_t) mutable {
    const nav::Building building = CurrentBuilding(config_, store_);
    nav::GoalCheckInputs in;
    in.costmap = costmap.get();
    in.building = &building;
    in.map = maps_.active()->name;
    in.grid_of = [this](const std::string& map) -> std::shared_ptr<const nav::OccupancyGrid> {
      try {
        return maps_.Grid(map);
      } catch (const MapEditError& e) {
        spdlog::warn("a floor's map '{}' cannot be read: {}", map, e.what());
        return nullptr;
      }
    };
    in.lift_controller = config_.building.controller.configured();
    auto checked = nav::CheckMissionGoals(std::move(order.goals), in);
    if (auto* refusal = std::get_if<nav::MissionRefusal>(&checked)) {
      spdlog::info("a mission from {} refused: {}",
                   order.origin, nav::Describe(*refusal, "goal " + std::to_string(refusal->goal.value_or(0))));
      done(std::move(*refusal));
      return;
    }
    MissionState state = missions_.Start(std::move(std::get<std::vector<nav::MissionGoal>>(checked)),
                                         order.speed_limit_mps);
    spdlog::info("mission {} from {}: {} goals", state.id, order.origin, state.goals.size());
    done(std::move(state));
  });
}

void RobotCore::SetPose(const PoseOrder& order, std::function<void(PoseResult)> done) const {
  if (config_.localization.source != LocalizationOptions::Source::kMonteCarlo) {
    done(PoseRefused{PoseRefusal::kNotLocalizing, "localization.source is not mcl: only mcl takes a pose"});
    return;
  }
  if (!(order.sigma_m >= 0.0 && order.sigma_m <= 10.0) ||
      !(order.sigma_rad >= 0.0 && order.sigma_rad <= std::numbers::pi)) {
    done(PoseRefused{PoseRefusal::kBadSpread, "sigma_m must be within [0, 10] m and sigma_yaw within [0, pi] rad"});
    return;
  }
  const auto map = maps_.active();
  if (!map->grid.WorldToCell(order.pose.translation())) {
    char detail[160];
    std::snprintf(detail, sizeof detail, "(%.3g, %.3g) is not on map '%s'", order.pose.x_m, order.pose.y_m,
                  map->name.c_str());
    done(PoseRefused{PoseRefusal::kOutsideMap, detail});
    return;
  }
  localization_.SetPose(order.pose, order.sigma_m, order.sigma_rad,
                        [done = std::move(done), origin = order.origin](PoseCheck check) {
                          if (!check.taken) {
                            done(PoseRefused{PoseRefusal::kBusy, check.detail});
                            return;
                          }
                          spdlog::info("pose from {} taken: {}", origin, check.detail);
                          done(std::move(check));
                        });
}

}  // namespace corridor::server
