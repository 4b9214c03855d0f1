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
    : config_(config),
      planner_(planner),
      missions_(missions),
      localization_(localization),
      maps_(maps),
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
      spdlog::info("a mission from {} refused: {}", order.origin,
                   nav::Describe(*refusal, "goal " + std::to_string(refusal->goal.value_or(0))));
      done(std::move(*refusal));
      return;
    }
    MissionState state =
        missions_.Start(std::move(std::get<std::vector<nav::MissionGoal>>(checked)), order.speed_limit_mps);
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
  if (auto off = OffMap(order.pose)) {
    done(PoseRefused{PoseRefusal::kOutsideMap, std::move(*off)});
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

nav::TransitionOutcome RobotCore::Command(MissionStep step, const std::string& id, std::string_view origin) const {
  nav::TransitionOutcome outcome = nav::TransitionOutcome::kNotFound;
  switch (step) {
    case MissionStep::kPause: outcome = missions_.Pause(id); break;
    case MissionStep::kResume: outcome = missions_.Resume(id); break;
    case MissionStep::kCancel: outcome = missions_.Cancel(id); break;
  }
  if (outcome == nav::TransitionOutcome::kOk) spdlog::info("mission {}: {} from {}", id, ToString(step), origin);
  return outcome;
}

std::optional<std::string> RobotCore::OffMap(const nav::Pose2& pose) const {
  const auto map = maps_.active();
  if (map->grid.WorldToCell(pose.translation())) return std::nullopt;
  char detail[160];
  std::snprintf(detail, sizeof detail, "(%.3g, %.3g) is not on map '%s'", pose.x_m, pose.y_m, map->name.c_str());
  return detail;
}

const char* ToString(MissionStep step) {
  switch (step) {
    case MissionStep::kPause: return "pause";
    case MissionStep::kResume: return "resume";
    case MissionStep::kCancel: return "cancel";
  }
  return "?";
}

}  // namespace corridor::server
