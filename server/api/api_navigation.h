// Planning and missions: POST /api/v1/plan, /api/v1/missions and their pause, resume and cancel, /api/v1/dock and
// /api/v1/undock; and the mission requests they share with the Open-RMF routes (api_rmf.h).
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

#include "nav/mission/mission.h"
#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

// A mission asked for over HTTP: its goals read from a request (places, floors, docks) and started through the core,
// answered 201 with the mission or 422 naming the first goal the core refuses.
class MissionRequests {
 public:
  MissionRequests(Bus& bus, const RobotCore& core, const MapLibrary& maps, const Store& store, const Config& config);

  // The goal `j` names: {x, y[, yaw][, floor]} or {place[, floor]} (a dock's place docks). ApiError 400 or 422 naming
  // `where` otherwise.
  nav::MissionGoal ParseGoal(const nlohmann::json& j, const std::string& where) const;
  // The goal that docks at the dock named `wanted` (name or id; the nearest when empty), 409 when docked already; the
  // goal that backs off the dock, 409 when not docked.
  std::vector<nav::MissionGoal> DockGoals(const std::string& wanted) const;
  std::vector<nav::MissionGoal> UndockGoals() const;
  // Starts a mission through `goals` for `origin` ("rest", "rmf") once the core finds each somewhere the robot can
  // stand; replies 201 with the mission (or what `started` makes of it), or 422 naming the first goal that is not.
  void Start(const Request& request, Reply reply, std::vector<nav::MissionGoal> goals, double speed_limit,
             const std::string& origin, std::function<nlohmann::json(const MissionState&)> started = nullptr) const;

 private:
  // The dock named `wanted` (name or id), or the nearest when empty; 422 when there is none.
  nav::Place FindDock(const std::string& wanted) const;

  Bus& bus_;
  const RobotCore& core_;
  const MapLibrary& maps_;
  const Store& store_;
  const Config& config_;
};

class NavigationApi {
 public:
  NavigationApi(Bus& bus, const RobotCore& core, const Store& store, PlannerService& planner,
                const MissionRequests& missions);
  void AddRoutes(Router& routes) const;

 private:
  void Plan(const Request& request, Reply reply) const;
  void StartMission(const Request& request, Reply reply) const;
  void Dock(const Request& request, Reply reply) const;
  void Undock(const Request& request, Reply reply) const;
  // Pauses, resumes or cancels mission `id`.
  void MissionAction(const Request& request, Reply reply, const std::string& id, MissionStep step) const;

  Bus& bus_;
  const RobotCore& core_;
  const Store& store_;
  PlannerService& planner_;
  const MissionRequests& missions_;
};

}  // namespace corridor::server
