#include "server/api/api_navigation.h"

#include <algorithm>
#include <cmath>

#include <limits>
#include <variant>

#include "nav/mission/docking.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

http::status StatusFor(nav::PlanError error) {
  switch (error) {
    case nav::PlanError::kCancelled: return http::status::service_unavailable;
    default: return http::status::unprocessable_entity;
  }
}

std::string TitleFor(nav::PlanError error) {
  switch (error) {
    case nav::PlanError::kStartOutsideMap: return "Start outside the map";
    case nav::PlanError::kStartOccupied: return "Start occupied";
    case nav::PlanError::kGoalOutsideMap: return "Goal outside the map";
    case nav::PlanError::kGoalOccupied: return "Goal occupied";
    case nav::PlanError::kNoPath: return "No path";
    case nav::PlanError::kCancelled: return "Plan cancelled";
    case nav::PlanError::kNone: break;
  }
  return "Plan failed";
}

json NumberOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

// A mission the core refused, as a 422 problem naming the goal by its place in the request's `list` ("waypoints").
ApiError RefusalError(const nav::MissionRefusal& refusal, const std::string& list) {
  const std::string detail =
      nav::Describe(refusal, refusal.goal ? list + "[" + std::to_string(*refusal.goal) + "]" : "");
  const char* title = "Mission refused";
  switch (refusal.reason) {
    case nav::GoalRefusal::kOutsideMap: title = "Goal outside the map"; break;
    case nav::GoalRefusal::kOccupied: title = "Goal occupied"; break;
    case nav::GoalRefusal::kInKeepOut: title = "Goal in a keep-out zone"; break;
    case nav::GoalRefusal::kUnknownFloor: title = "Unknown floor"; break;
    case nav::GoalRefusal::kNotOnFloor: title = "Not on a floor"; break;
    case nav::GoalRefusal::kNoLiftController: title = "No lift controller"; break;
    case nav::GoalRefusal::kNoLiftRoute: title = "No way between floors"; break;
  }
  return ApiError(http::status::unprocessable_entity, title, detail, nav::ToString(refusal.reason));
}

}  // namespace

MissionRequests::MissionRequests(Bus& bus, const RobotCore& core, const MapLibrary& maps, const Store& store,
                                 const Config& config)
    : bus_(bus), core_(core), maps_(maps), store_(store), config_(config) {}

nav::MissionGoal MissionRequests::ParseGoal(const json& j, const std::string& where) const {
  if (!j.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "'" + where + "' must be an object");
  nav::MissionGoal goal;
  // On another floor of the building: its map's places and frame.
  std::string map = maps_.active()->name;
  if (j.contains("floor")) {
    if (!j["floor"].is_string() || j["floor"].get<std::string>().empty()) {
      throw ApiError(http::status::bad_request, "Invalid request", "'" + where + ".floor' must be a floor's name");
    }
    goal.floor = j["floor"].get<std::string>();
    const nav::Building building = BuildingOf(config_.building);
    const nav::Floor* floor = building.FloorNamed(goal.floor);
    if (floor == nullptr) {
      throw ApiError(http::status::unprocessable_entity, "Unknown floor",
                     "'" + where + "': the building has no floor '" + goal.floor + "'", "unknown_floor");
    }
    map = floor->map;
  }
  if (j.contains("place")) {
    AllowOnlyKeys(j, {"place", "floor"}, where);
    if (!j["place"].is_string()) {
      throw ApiError(http::status::bad_request, "Invalid request", "'" + where + ".place' must be a place name");
    }
    const std::string wanted = j["place"].get<std::string>();
    for (const nav::Place& p : store_.Places(map)) {
      if (p.name == wanted || p.id == wanted) {
        if (p.kind == nav::PlaceKind::kDock) {
          nav::MissionGoal dock = nav::DockGoal(p, config_.mission.docking.dock);
          dock.floor = goal.floor;
          return dock;
        }
        goal.place = wanted;
        goal.pose = p.pose;
        goal.has_yaw = true;
        return goal;
      }
    }
    throw ApiError(http::status::unprocessable_entity, "Unknown place",
                   "'" + where + "': no place named '" + wanted + "' on map '" + map + "'", "unknown_place");
  }
  AllowOnlyKeys(j, {"x", "y", "yaw", "floor"}, where);
  goal.pose.x_m = RequireNumber(j, "x", where);
  goal.pose.y_m = RequireNumber(j, "y", where);
  if (j.contains("yaw")) {
    goal.pose.yaw_rad = nav::WrapAngle(RequireNumber(j, "yaw", where));
    goal.has_yaw = true;
  }
  return goal;
}

nav::Place MissionRequests::FindDock(const std::string& wanted) const {
  const auto map = maps_.active();
  const std::vector<nav::Place> places = store_.Places(map->name);
  if (wanted.empty()) {
    const auto pose = bus_.Get(topics::kPose).latest();
    if (auto dock = nav::NearestDock(places, pose ? pose->pose.translation() : Eigen::Vector2d::Zero())) return *dock;
    throw ApiError(http::status::unprocessable_entity, "No dock",
                   "map '" + map->name + "' has no dock (a place of kind dock)", "no_dock");
  }
  for (const nav::Place& p : places) {
    if (p.name != wanted && p.id != wanted) continue;
    if (p.kind == nav::PlaceKind::kDock) return p;
    throw ApiError(http::status::unprocessable_entity, "Not a dock", "the place '" + wanted + "' is not a dock",
                   "not_a_dock");
  }
  throw ApiError(http::status::unprocessable_entity, "Unknown dock",
                 "no dock named '" + wanted + "' on map '" + map->name + "'", "unknown_place");
}

std::vector<nav::MissionGoal> MissionRequests::DockGoals(const std::string& wanted) const {
  const nav::Place dock = FindDock(wanted);
  if (core_.Docked()) {
    throw ApiError(http::status::conflict, "Docked", "the robot stands on a dock already", "docked");
  }
  return {nav::DockGoal(dock, config_.mission.docking.dock)};
}

std::vector<nav::MissionGoal> MissionRequests::UndockGoals() const {
  if (!core_.Docked()) {
    throw ApiError(http::status::conflict, "Not docked", "the robot is not on a dock", "not_docked");
  }
  const auto pose = bus_.Get(topics::kPose).latest();
  return {nav::UndockGoal(pose ? std::optional<nav::Pose2>(pose->pose) : std::nullopt, config_.mission.docking.dock)};
}

void MissionRequests::Start(const Request& request, Reply reply, std::vector<nav::MissionGoal> goals,
                            double speed_limit, const std::string& origin,
                            std::function<json(const MissionState&)> started) const {
  // Every waypoint must be somewhere the robot can stand: the core says which one is not before anything moves.
  core_.StartMission({std::move(goals), speed_limit, origin}, [request, reply, started](MissionResult result) {
    reply(Respond(request, [&]() -> Response {
      if (const auto* refusal = std::get_if<nav::MissionRefusal>(&result)) throw RefusalError(*refusal, "waypoints");
      const MissionState& state = std::get<MissionState>(result);
      Response res = JsonResponse(request, started ? started(state) : ToJson(state), http::status::created);
      res.set(http::field::location, "/api/v1/missions/" + state.id);
      return res;
    }));
  });
}

NavigationApi::NavigationApi(Bus& bus, const RobotCore& core, const Store& store, PlannerService& planner,
                             const MissionRequests& missions)
    : bus_(bus), core_(core), store_(store), planner_(planner), missions_(missions) {}

void NavigationApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::post, "/api/v1/plan", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) { Plan(r, std::move(reply)); });
  routes.Add(http::verb::post, "/api/v1/missions", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) { StartMission(r, std::move(reply)); });
  routes.Add(http::verb::post, "/api/v1/dock", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) { Dock(r, std::move(reply)); });
  routes.Add(http::verb::post, "/api/v1/undock", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) { Undock(r, std::move(reply)); });
  routes.Add(http::verb::get, "/api/v1/missions", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"missions", store_.Missions(50)}});
             }));
  routes.Add(http::verb::get, "/api/v1/missions/{id}", Access::kViewer, Sync([this](const Request& r, const Params& p) {
               const std::string& id = p.at("id");
               if (auto state = core_.Mission(id)) return JsonResponse(r, ToJson(*state));
               if (auto doc = store_.Mission(id)) return JsonResponse(r, *doc);
               throw ApiError(http::status::not_found, "Not found", "no mission " + id);
             }));
  // The console's emergency stop: the robot stopped and the mission in progress paused, in one request.
  routes.Add(http::verb::post, "/api/v1/stop", Access::kOperator, [this](const Request& r, const Params&, Reply reply) {
    core_.Stop("rest", [r, reply = std::move(reply)](std::optional<MissionState> paused) {
      reply(Respond(r, [&] {
        return JsonResponse(r, {{"stopped", true}, {"paused", paused ? ToJson(*paused) : json(nullptr)}});
      }));
    });
  });
  for (const MissionStep step : {MissionStep::kPause, MissionStep::kResume, MissionStep::kCancel}) {
    routes.Add(http::verb::post, std::string("/api/v1/missions/{id}/") + ToString(step), Access::kOperator,
               [this, step](const Request& r, const Params& p, Reply reply) {
                 MissionAction(r, std::move(reply), p.at("id"), step);
               });
  }
}

void NavigationApi::Plan(const Request& request, Reply reply) const {
  const json body = ParseJsonBody(request);
  AllowOnlyKeys(body, {"start", "goal"}, "");
  if (!body.contains("goal")) throw ApiError(http::status::bad_request, "Invalid request", "missing 'goal'");
  const nav::MissionGoal goal = missions_.ParseGoal(body["goal"], "goal");
  PlanRequest plan;
  plan.goal = goal.pose.translation();
  if (goal.has_yaw) plan.goal_yaw = goal.pose.yaw_rad;
  if (body.contains("start")) {
    plan.start = missions_.ParseGoal(body["start"], "start").pose.translation();
  } else {
    const auto pose = bus_.Get(topics::kPose).latest();
    if (!pose) throw ApiError(http::status::service_unavailable, "No pose", "the robot does not know where it is yet");
    plan.start = pose->pose.translation();
    plan.robot_at_start = true;
  }
  planner_.Plan(std::move(plan), [request, reply](PlanReply r) {
    reply(Respond(request, [&]() -> Response {
      if (!r.result.ok()) {
        throw ApiError(StatusFor(r.result.error), TitleFor(r.result.error), r.result.detail,
                       nav::ToString(r.result.error));
      }
      const nav::Plan& p = r.result.plan;
      json path = json::array();
      for (const nav::Waypoint& w : p.waypoints) {
        path.push_back({{"x", w.pose.x_m},
                        {"y", w.pose.y_m},
                        {"yaw", w.pose.yaw_rad},
                        {"speed_limit_mps", NumberOrNull(w.speed_limit_mps)}});
      }
      return JsonResponse(request, {{"path", path},
                                    {"length_m", p.length_m},
                                    {"min_clearance_m", p.min_clearance_m},
                                    {"mean_clearance_m", p.mean_clearance_m},
                                    {"expanded", p.expanded},
                                    {"planning_ms", r.planning_ms},
                                    {"costmap_ms", r.costmap_ms}});
    }));
  });
}

void NavigationApi::StartMission(const Request& request, Reply reply) const {
  const json body = ParseJsonBody(request);
  AllowOnlyKeys(body, {"waypoints", "speed_limit_mps"}, "");
  const auto list = body.find("waypoints");
  if (list == body.end() || !list->is_array() || list->empty() || list->size() > 100) {
    throw ApiError(http::status::bad_request, "Invalid request", "'waypoints' must be a list of 1 to 100 waypoints");
  }
  std::vector<nav::MissionGoal> goals;
  for (std::size_t i = 0; i < list->size(); ++i)
    goals.push_back(missions_.ParseGoal((*list)[i], "waypoints[" + std::to_string(i) + "]"));
  double speed_limit = std::numeric_limits<double>::infinity();
  if (body.contains("speed_limit_mps")) {
    speed_limit = RequireNumber(body, "speed_limit_mps", "");
    if (speed_limit <= 0.0)
      throw ApiError(http::status::bad_request, "Invalid request", "'speed_limit_mps' must be > 0");
  }
  missions_.Start(request, std::move(reply), std::move(goals), speed_limit, "rest");
}

void NavigationApi::Dock(const Request& request, Reply reply) const {
  const json body = request.body().empty() ? json::object() : ObjectBody(request, {"dock"});
  if (body.contains("dock") && (!body["dock"].is_string() || body["dock"].get<std::string>().empty())) {
    throw ApiError(http::status::bad_request, "Invalid request", "'dock' must be a dock's name or id");
  }
  missions_.Start(request, std::move(reply), missions_.DockGoals(body.value("dock", "")),
                  std::numeric_limits<double>::infinity(), "rest");
}

void NavigationApi::Undock(const Request& request, Reply reply) const {
  if (!request.body().empty()) {
    const json body = ParseJsonBody(request);
    if (!body.is_object() || !body.empty()) {
      throw ApiError(http::status::bad_request, "Invalid request", "undock takes no body (or {})");
    }
  }
  missions_.Start(request, std::move(reply), missions_.UndockGoals(), std::numeric_limits<double>::infinity(), "rest");
}

void NavigationApi::MissionAction(const Request& request, Reply reply, const std::string& id, MissionStep step) const {
  core_.Command(step, id, "rest", [request, reply = std::move(reply), id, step](MissionNode::Outcome outcome) {
    reply(Respond(request, [&]() -> Response {
      if (outcome.outcome == nav::TransitionOutcome::kNotFound || !outcome.mission) {
        throw ApiError(http::status::not_found, "Not found", "no mission " + id + " in progress");
      }
      if (outcome.outcome == nav::TransitionOutcome::kConflict) {
        throw ApiError(
            http::status::conflict, "Not allowed now",
            std::string("cannot ") + ToString(step) + " a mission that is " + nav::ToString(outcome.mission->status),
            "invalid_transition");
      }
      return JsonResponse(request, ToJson(*outcome.mission));
    }));
  });
}

}  // namespace corridor::server
