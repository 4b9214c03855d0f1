#include "server/api/api_rmf.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "server/api/api_localization.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

std::uint64_t RequireCommandId(const json& body) {
  const auto it = body.find("cmd_id");
  if (it == body.end() || !it->is_number_integer() || it->get<std::int64_t>() < 0) {
    throw ApiError(http::status::bad_request, "Invalid request", "'cmd_id' must be a whole number >= 0");
  }
  return it->get<std::uint64_t>();
}

// [x, y, yaw], the template's pose.
nav::Pose2 RequirePose(const json& body) {
  const auto it = body.find("pose");
  if (it == body.end() || !it->is_array() || it->size() != 3) {
    throw ApiError(http::status::bad_request, "Invalid request", "'pose' must be [x, y, yaw]");
  }
  double v[3];
  for (int i = 0; i < 3; ++i) {
    if (!(*it)[i].is_number() || !std::isfinite((*it)[i].get<double>())) {
      throw ApiError(http::status::bad_request, "Invalid request", "'pose' must be three finite numbers");
    }
    v[i] = (*it)[i].get<double>();
  }
  return {v[0], v[1], nav::WrapAngle(v[2])};
}

std::string RequireText(const json& body, const char* key) {
  const auto it = body.find(key);
  if (it == body.end() || !it->is_string() || it->get<std::string>().empty()) {
    throw ApiError(http::status::bad_request, "Invalid request",
                   std::string("'") + key + "' must be a non-empty string");
  }
  return it->get<std::string>();
}

}  // namespace

RmfApi::RmfApi(Bus& bus, const RobotCore& core, const MapLibrary& maps, const Store& store,
               const BuildingOptions& building, const MissionRequests& missions, std::string robot_name)
    : bus_(bus),
      core_(core),
      maps_(maps),
      store_(store),
      building_(building),
      missions_(missions),
      robot_name_(std::move(robot_name)) {}

RmfSample RmfApi::Sample() const {
  const std::shared_ptr<const RobotState> state = core_.State();
  RmfSample s;
  s.name = robot_name_;
  s.map = state->map;
  if (const auto& pose = state->pose) {
    s.has_pose = true;
    s.x = pose->pose.x_m;
    s.y = pose->pose.y_m;
    s.yaw = pose->pose.yaw_rad;
  }
  if (const auto& battery = state->battery) {
    s.battery = battery->charge;
    s.charging = battery->charging;
  }
  if (const auto& mission = state->mission) {
    s.mission_id = mission->id;
    s.mission_status = nav::ToString(mission->status);
    s.mission_error = mission->error;
  }
  if (const auto& command = state->command; command && command->mode == nav::ControlMode::kStopped) {
    s.stopped = true;
    s.stop_reason = nav::ToString(command->reason);
  }
  if (const auto& localization = state->localization) {
    s.lost = localization->estimate.health == nav::LocalizationHealth::kLost;
  }
  s.unix_millis =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  return s;
}

void RmfApi::AddRoutes(Router& routes) const {
  // The robot's map, or (with a building) another floor's: that floor's name; else 422.
  const auto require_map = [this](const json& body) -> std::string {
    const std::string map = RequireText(body, "map_name");
    const std::string active = maps_.active()->name;
    if (map == active) return "";
    const nav::Building building = BuildingOf(building_);
    if (const nav::Floor* floor = building.FloorOfMap(map)) return floor->name;
    throw ApiError(http::status::unprocessable_entity, "Not the robot's map",
                   "the robot is on map '" + active + "', not '" + map + "' (nor is that a floor of its building)",
                   "wrong_map");
  };
  // A mission that carries command `cmd_id`: its reply names both.
  const auto carried = [this](std::uint64_t cmd_id) {
    return [commands = commands_, cmd_id](const MissionState& state) {
      commands->Carried(cmd_id, state.id);
      return json{{"cmd_id", cmd_id}, {"mission", state.id}};
    };
  };
  routes.Add(http::verb::post, "/api/v1/rmf/navigate", Access::kOperator,
             [this, require_map, carried](const Request& r, const Params&, Reply reply) {
               const json body = ObjectBody(r, {"cmd_id", "pose", "map_name", "speed_limit"});
               const std::uint64_t cmd_id = RequireCommandId(body);
               nav::MissionGoal goal;
               goal.pose = RequirePose(body);
               goal.has_yaw = true;
               goal.floor = require_map(body);  // on another floor: through the lifts
               double speed_limit = std::numeric_limits<double>::infinity();
               if (body.contains("speed_limit")) {
                 const double v = RequireNumber(body, "speed_limit", "");
                 if (v < 0.0)
                   throw ApiError(http::status::bad_request, "Invalid request", "'speed_limit' must be >= 0");
                 if (v > 0.0) speed_limit = v;  // the template's 0.0: none
               }
               missions_.Start(r, std::move(reply), {goal}, speed_limit, "rmf", carried(cmd_id));
             });
  routes.Add(http::verb::post, "/api/v1/rmf/dock", Access::kOperator,
             [this, carried](const Request& r, const Params&, Reply reply) {
               const json body = ObjectBody(r, {"cmd_id", "dock_name"});
               const std::uint64_t cmd_id = RequireCommandId(body);
               missions_.Start(r, std::move(reply), missions_.DockGoals(RequireText(body, "dock_name")),
                               std::numeric_limits<double>::infinity(), "rmf", carried(cmd_id));
             });
  routes.Add(http::verb::post, "/api/v1/rmf/start_activity", Access::kOperator,
             [this, carried](const Request& r, const Params&, Reply reply) {
               const json body = ObjectBody(r, {"cmd_id", "activity", "label"});
               const std::uint64_t cmd_id = RequireCommandId(body);
               const std::string activity = RequireText(body, "activity");
               const std::string label =
                   body.contains("label") && body["label"].is_string() ? body["label"].get<std::string>() : "";
               std::vector<nav::MissionGoal> goals;
               if (activity == "dock") {
                 goals = missions_.DockGoals(label);
               } else if (activity == "undock") {
                 goals = missions_.UndockGoals();
               } else {
                 throw ApiError(
                     http::status::unprocessable_entity, "Unknown activity",
                     "activities are \"dock\" (label: the dock, or empty for the nearest) and \"undock\", not '" +
                         activity + "'",
                     "unknown_activity");
               }
               missions_.Start(r, std::move(reply), std::move(goals), std::numeric_limits<double>::infinity(), "rmf",
                               carried(cmd_id));
             });
  routes.Add(http::verb::post, "/api/v1/rmf/stop", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) {
               const json body = ObjectBody(r, {"cmd_id"});
               const std::uint64_t cmd_id = RequireCommandId(body);
               const auto stopped = [this, r, reply, cmd_id] {
                 reply(Respond(r, [&] {
                   commands_->Done(cmd_id);
                   return JsonResponse(r, {{"cmd_id", cmd_id}, {"completed", true}});
                 }));
               };
               // Answered once the mission is cancelled, so that the command it carried reads as such.
               if (const auto mission = bus_.Get(topics::kMission).latest()) {
                 core_.Command(MissionStep::kCancel, mission->id, "rmf",
                               [stopped](const MissionNode::Outcome&) { stopped(); });
               } else {
                 stopped();
               }
             });
  routes.Add(
      http::verb::post, "/api/v1/rmf/localize", Access::kOperator,
      [this, require_map](const Request& r, const Params&, Reply reply) {
        const json body = ObjectBody(r, {"cmd_id", "pose", "map_name"});
        const std::uint64_t cmd_id = RequireCommandId(body);
        PoseOrder order;
        order.pose = RequirePose(body);
        order.origin = "rmf";
        const std::string floor = require_map(body);
        RequireLocalizing(core_);
        if (!floor.empty()) {
          // The fleet adapter took the robot to another floor itself (it rode the lift): that floor's map.
          if (const auto refused = core_.SelectMap(RequireText(body, "map_name"), "rmf")) {
            if (refused->reason == MapRefusal::kMissionInProgress) {
              throw ApiError(http::status::conflict, "Mission in progress", refused->detail, "mission_in_progress");
            }
            throw ApiError(http::status::unprocessable_entity, "Map unusable", refused->detail, "wrong_map");
          }
        }
        core_.SetPose(order, [this, r, reply, cmd_id](PoseResult result) {
          reply(Respond(r, [&]() -> Response {
            if (const auto* refused = std::get_if<PoseRefused>(&result)) {
              if (refused->reason == PoseRefusal::kOutsideMap) {
                throw ApiError(http::status::unprocessable_entity, "Outside the map", refused->detail, "outside_map");
              }
              throw ApiError(http::status::conflict, "Not now", refused->detail, "not_now");
            }
            commands_->Done(cmd_id);
            return JsonResponse(r, {{"cmd_id", cmd_id}, {"completed", true}});
          }));
        });
      });
  routes.Add(http::verb::get, "/api/v1/rmf/position", Access::kViewer, Sync([this](const Request& r, const Params&) {
               const RmfSample s = Sample();
               if (!s.has_pose) {
                 throw ApiError(http::status::service_unavailable, "No pose yet",
                                "the robot does not know where it is yet");
               }
               return JsonResponse(r, {{"position", {s.x, s.y, s.yaw}}, {"map_name", s.map}});
             }));
  routes.Add(http::verb::get, "/api/v1/rmf/battery_soc", Access::kViewer, Sync([this](const Request& r, const Params&) {
               const RmfSample s = Sample();
               if (!s.battery) {
                 throw ApiError(http::status::service_unavailable, "No battery",
                                "nothing reports this robot's battery");
               }
               return JsonResponse(r, {{"battery_soc", *s.battery}});
             }));
  routes.Add(http::verb::get, "/api/v1/rmf/map", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"map_name", maps_.active()->name}});
             }));
  routes.Add(
      http::verb::get, "/api/v1/rmf/is_command_completed", Access::kViewer,
      Sync([this](const Request& r, const Params&) {
        const std::string text = QueryValue(r.target(), "cmd_id");
        if (text.empty()) throw ApiError(http::status::bad_request, "Invalid request", "'cmd_id' is required");
        const std::uint64_t cmd_id = ParseCount(text, "'cmd_id' a whole number >= 0");
        const auto command = commands_->Find(cmd_id);
        if (!command) throw ApiError(http::status::not_found, "Not found", "no command " + text);
        if (command->mission_id.empty()) {
          return JsonResponse(r, {{"cmd_id", cmd_id}, {"completed", true}, {"status", "succeeded"}, {"error", ""}});
        }
        const auto state = core_.Mission(command->mission_id);
        const auto stored = state ? std::nullopt : store_.Mission(command->mission_id);
        const std::string status = state    ? nav::ToString(state->status)
                                   : stored ? stored->value("status", "canceled")
                                            : "canceled";
        const std::string error = state ? state->error : stored ? stored->value("error", "") : "";
        return JsonResponse(r, {{"cmd_id", cmd_id},
                                {"completed", status == "succeeded"},
                                {"status", status},
                                {"mission", command->mission_id},
                                {"error", error}});
      }));
  routes.Add(http::verb::get, "/api/v1/rmf/robot_state", Access::kViewer,
             Sync([this](const Request& r, const Params&) { return JsonResponse(r, RmfRobotState(Sample())); }));
}

}  // namespace corridor::server
