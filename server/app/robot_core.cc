#include "server/app/robot_core.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <numbers>

#include <spdlog/spdlog.h>

#include "nav/demand.h"
#include "nav/mission/docking.h"
#include "server/fleet/doors.h"
#include "server/runtime/topics.h"

namespace corridor::server {

nav::Building CurrentBuilding(const Config& config, const Store& store) {
  nav::Building building = BuildingOf(config.building);
  for (auto& [lift, stop] : store.LiftStops()) nav::PutStop(building, lift, std::move(stop));
  return building;
}

RobotCore::RobotCore(const Config& config, Bus& bus, const drivers::Clock& clock, const Lifecycle& lifecycle,
                     PlannerService& planner, MissionNode& missions, LocalizationNode& localization, MapLibrary& maps,
                     const Store& store)
    : config_(config),
      bus_(bus),
      clock_(clock),
      lifecycle_(lifecycle),
      planner_(planner),
      missions_(missions),
      localization_(localization),
      maps_(maps),
      store_(store),
      start_ns_(clock.Now()),
      tick_ns_(static_cast<drivers::TimeNs>(1e9 / config.server.stream_rate_hz)) {}

std::shared_ptr<const RobotState> RobotCore::State() const {
  const drivers::TimeNs now = clock_.Now();
  const auto map = maps_.active();  // a map switched (a floor changed) is news at once, whoever switched it
  std::lock_guard lock(state_mutex_);
  if (!state_ || now - state_->stamp_ns >= tick_ns_ || now < state_->stamp_ns || map->name != state_->map ||
      map->revision != state_->map_revision) {
    state_ = std::make_shared<const RobotState>(Take());
  }
  return state_;
}

void RobotCore::Stale() const {
  std::lock_guard lock(state_mutex_);
  state_.reset();
}

RobotState RobotCore::Take() const {
  RobotState s;
  s.stamp_ns = clock_.Now();
  s.uptime_s = drivers::ToSeconds(s.stamp_ns - start_ns_);
  s.pose = bus_.Get(topics::kPose).latest();
  s.odometry = bus_.Get(topics::kOdometry).latest();
  s.command = bus_.Get(topics::kCmdVel).latest();
  s.localization = bus_.Get(topics::kLocalization).latest();
  s.mission = bus_.Get(topics::kMission).latest();
  s.battery = bus_.Get(topics::kBattery).latest();
  s.devices = bus_.Get(topics::kDevices).latest();
  s.fleet = bus_.Get(topics::kFleetOrder).latest();
  s.face = bus_.Get(topics::kFaceExpression).latest();
  s.tracked = bus_.Get(topics::kTrackedObjects).latest();
  s.latency = bus_.Get(topics::kControlLatency).latest();
  s.sim_true_pose = bus_.Get(topics::kSimTruePose).latest();
  s.sim_pedestrians = bus_.Get(topics::kSimPedestrians).latest();
  s.docked = missions_.docked();
  // CPU time is real time's: sampled on the steady clock even when the graph runs on the simulator's.
  s.process = process_.Sample(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
  const auto map = maps_.active();
  s.map = map->name;
  s.map_revision = map->revision;
  const auto traffic = planner_.traffic();
  s.map_traffic = traffic && traffic->size() == map->grid.cells().size();
  // Floors are the configuration's alone: no store read on every state.
  const nav::Building building = BuildingOf(config_.building);
  if (const nav::Floor* floor = building.FloorOfMap(map->name)) s.floor = floor->name;
  s.nodes = nlohmann::json::array();
  for (const auto& node : lifecycle_.nodes()) s.nodes.push_back(node->Status());
  s.text = ToJson(s, config_).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return s;
}

nav::GoalCheckResult RobotCore::Check(std::vector<nav::MissionGoal> goals, const nav::Costmap& costmap) const {
  const nav::Building building = CurrentBuilding(config_, store_);
  nav::GoalCheckInputs in;
  in.costmap = &costmap;
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
  in.lift_controller = LiftsAnswer(config_);
  return nav::CheckMissionGoals(std::move(goals), in);
}

void RobotCore::StartMission(MissionOrder order, std::function<void(MissionResult)> done) const {
  DEMAND(!order.goals.empty());
  planner_.WithCostmap([this, order = std::move(order), done = std::move(done)](
                           std::shared_ptr<const nav::Costmap> costmap, std::uint64_t) mutable {
    auto checked = Check(std::move(order.goals), *costmap);
    if (auto* refusal = std::get_if<nav::MissionRefusal>(&checked)) {
      spdlog::info("a mission from {} refused: {}", order.origin,
                   nav::Describe(*refusal, "goal " + std::to_string(refusal->goal.value_or(0))));
      done(std::move(*refusal));
      return;
    }
    missions_.Start(std::move(std::get<std::vector<nav::MissionGoal>>(checked)), order.speed_limit_mps,
                    [this, origin = std::move(order.origin), done = std::move(done)](MissionState state) {
                      Stale();
                      spdlog::info("mission {} from {}: {} goals", state.id, origin, state.goals.size());
                      done(std::move(state));
                    });
  });
}

void RobotCore::ExtendMission(const std::string& id, std::vector<nav::MissionGoal> goals, std::string origin,
                              std::function<void(ExtendResult)> done) const {
  DEMAND(!goals.empty());
  planner_.WithCostmap([this, id, goals = std::move(goals), origin = std::move(origin), done = std::move(done)](
                           std::shared_ptr<const nav::Costmap> costmap, std::uint64_t) mutable {
    auto checked = Check(std::move(goals), *costmap);
    if (auto* refusal = std::get_if<nav::MissionRefusal>(&checked)) {
      spdlog::info("mission {}: an extension from {} refused: {}", id, origin,
                   nav::Describe(*refusal, "goal " + std::to_string(refusal->goal.value_or(0))));
      done(std::move(*refusal));
      return;
    }
    missions_.Extend(id, std::get<std::vector<nav::MissionGoal>>(checked),
                     [this, id, origin = std::move(origin), done = std::move(done)](MissionNode::Outcome outcome) {
                       if (outcome.outcome == nav::TransitionOutcome::kOk) {
                         Stale();
                         spdlog::info("mission {}: extended by {}", id, origin);
                       }
                       done(outcome.outcome);
                     });
  });
}

void RobotCore::SetPose(const PoseOrder& order, std::function<void(PoseResult)> done) const {
  if (auto why = NotLocalizing()) {
    done(PoseRefused{PoseRefusal::kNotLocalizing, std::move(*why)});
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

void RobotCore::Command(MissionStep step, const std::string& id, std::string_view origin,
                        std::function<void(MissionNode::Outcome)> done) const {
  missions_.Step(step, id,
                 [this, step, id, origin = std::string(origin), done = std::move(done)](MissionNode::Outcome outcome) {
                   if (outcome.outcome == nav::TransitionOutcome::kOk) {
                     Stale();
                     spdlog::info("mission {}: {} from {}", id, ToString(step), origin);
                   }
                   if (done) done(std::move(outcome));
                 });
}

void RobotCore::Stop(std::string_view origin, std::function<void(std::optional<MissionState>)> done) const {
  Teleop({}, origin);
  spdlog::warn("stop from {}", origin);
  const auto mission = bus_.Get(topics::kMission).latest();
  if (!mission || mission->status != nav::MissionStatus::kActive) {
    if (done) done(std::nullopt);
    return;
  }
  Command(MissionStep::kPause, mission->id, origin, [done = std::move(done)](MissionNode::Outcome outcome) {
    // A mission that ended meanwhile has nothing to pause.
    if (done) done(outcome.outcome == nav::TransitionOutcome::kOk ? outcome.mission : std::nullopt);
  });
}

std::optional<MapRefused> RobotCore::SelectMap(const std::string& name, std::string_view origin) const {
  if (const auto mission = bus_.Get(topics::kMission).latest(); mission && nav::InProgress(mission->status)) {
    return MapRefused{MapRefusal::kMissionInProgress, "cancel the mission before changing maps"};
  }
  try {
    maps_.Select(name);
  } catch (const MapEditError& e) {
    return MapRefused{MapRefusal::kUnusable, e.what()};
  }
  Stale();
  spdlog::info("map '{}' in use, from {}", name, origin);
  return std::nullopt;
}

std::optional<MissionState> RobotCore::Mission(const std::string& id) const {
  const auto latest = bus_.Get(topics::kMission).latest();
  if (!latest || latest->id != id) return std::nullopt;
  return *latest;
}

bool RobotCore::Docked() const { return missions_.docked(); }

std::optional<nav::MissionGoal> RobotCore::NearestDock(const nav::Pose2& robot) const {
  const auto dock = nav::NearestDock(store_.Places(maps_.active()->name), robot.translation());
  if (!dock) return std::nullopt;
  return nav::DockGoal(*dock, config_.mission.docking.dock);
}

std::optional<std::string> RobotCore::OffMap(const nav::Pose2& pose) const {
  const auto map = maps_.active();
  if (map->grid.WorldToCell(pose.translation())) return std::nullopt;
  char detail[160];
  std::snprintf(detail, sizeof detail, "(%.3g, %.3g) is not on map '%s'", pose.x_m, pose.y_m, map->name.c_str());
  return detail;
}

nav::Twist2 RobotCore::Teleop(const nav::Twist2& asked, std::string_view origin) const {
  bus_.Get(topics::kTeleop).Publish(TeleopCommand{asked, clock_.Now(), std::string(origin)});
  const SafetyOptions& s = config_.safety;
  return {std::clamp(asked.linear_mps, -s.max_linear_mps, s.max_linear_mps),
          std::clamp(asked.angular_rps, -s.max_angular_rps, s.max_angular_rps)};
}

std::optional<std::string> RobotCore::NotLocalizing() const {
  using Source = LocalizationOptions::Source;
  switch (config_.localization.source) {
    case Source::kMonteCarlo: return std::nullopt;
    case Source::kOdometry: return "localization.source is odometry: only mcl takes a pose, maps or relocalizes";
    case Source::kSimTruth: return "localization.source is sim_truth: only mcl takes a pose, maps or relocalizes";
  }
  return "localization.source is not mcl";
}

std::optional<MappingRefused> RobotCore::StartMapping(const std::string& name, std::string_view origin) const {
  if (auto why = NotLocalizing()) return MappingRefused{MappingRefusal::kNotLocalizing, std::move(*why)};
  if (maps_.Contains(name)) return MappingRefused{MappingRefusal::kMapExists, "a map named '" + name + "' exists"};
  if (const auto state = bus_.Get(topics::kMapping).latest(); state && state->active) {
    return MappingRefused{MappingRefusal::kAlreadyMapping, "mapping '" + state->name + "' is under way"};
  }
  LocalizationCommand command;
  command.kind = LocalizationCommand::Kind::kStartMapping;
  command.name = name;
  bus_.Get(topics::kLocalizationCommand).Publish(command);
  spdlog::info("mapping '{}' from {}", name, origin);
  return std::nullopt;
}

std::variant<std::string, MappingRefused> RobotCore::StopMapping(std::string_view origin) const {
  const auto state = bus_.Get(topics::kMapping).latest();
  if (!state || !state->active) return MappingRefused{MappingRefusal::kNotMapping, "no mapping is under way"};
  LocalizationCommand command;
  command.kind = LocalizationCommand::Kind::kStopMapping;
  bus_.Get(topics::kLocalizationCommand).Publish(command);
  spdlog::info("mapping '{}' stopped from {}", state->name, origin);
  return state->name;
}

std::optional<MappingRefused> RobotCore::Relocalize(std::string_view origin) const {
  if (auto why = NotLocalizing()) return MappingRefused{MappingRefusal::kNotLocalizing, std::move(*why)};
  LocalizationCommand command;
  command.kind = LocalizationCommand::Kind::kRelocalize;
  bus_.Get(topics::kLocalizationCommand).Publish(command);
  spdlog::info("relocalizing, from {}", origin);
  return std::nullopt;
}

std::optional<MappingRefused> RobotCore::Explore(std::string_view origin) const {
  if (auto why = NotLocalizing()) return MappingRefused{MappingRefusal::kNotLocalizing, std::move(*why)};
  bus_.Get(topics::kExploreCommand).Publish(ExploreCommand{std::string(origin)});
  return std::nullopt;
}

void RobotCore::MapEdited(std::string_view what, std::string_view origin) const {
  const auto map = maps_.active();
  bus_.Get(topics::kMapInUse).Publish(MapInUseOf(map, config_, store_));
  Stale();
  spdlog::info("map '{}': {} edited, from {}", map->name, what, origin);
}

MapInUse MapInUseOf(const std::shared_ptr<const ActiveMap>& map, const Config& config, const Store& store) {
  MapInUse in_use;
  in_use.name = map->name;
  in_use.grid = std::shared_ptr<const nav::OccupancyGrid>(map, &map->grid);
  in_use.zones = store.Zones(map->name);
  if (DoorsAnswer(config)) {
    for (const MapDoor& d : DoorsOfMap(config, store.Doors(map->name), map->name, Simulated(config))) {
      in_use.doors.push_back(d.door);
    }
  }
  in_use.building = CurrentBuilding(config, store);
  return in_use;
}

}  // namespace corridor::server
