#include "server/api/api_sim.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

// {x, y, yaw} of `body`, on the active map (else 422 outside_map).
nav::Pose2 PoseOnMap(const RobotCore& core, const json& body) {
  const nav::Pose2 pose{RequireNumber(body, "x", ""), RequireNumber(body, "y", ""),
                        nav::WrapAngle(RequireNumber(body, "yaw", ""))};
  if (auto off = core.OffMap(pose)) {
    throw ApiError(http::status::unprocessable_entity, "Pose outside the map", *off, "outside_map");
  }
  return pose;
}

}  // namespace

SimulatorApi::SimulatorApi(drivers::sim::SimRobot* sim, const RobotCore& core, Executor& control)
    : sim_(sim), core_(core), control_(control) {}

drivers::sim::SimRobot& SimulatorApi::Sim() const {
  if (sim_ == nullptr) throw ApiError(http::status::not_found, "No simulator", "only a simulated robot has these");
  return *sim_;
}

void SimulatorApi::AddRoutes(Router& routes) const {
  AddFaultRoutes(routes);
  routes.Add(http::verb::put, "/api/v1/sim/pose", Access::kOperator, Sync([this](const Request& r, const Params&) {
               drivers::sim::SimRobot& sim = Sim();
               const json body = ObjectBody(r, {"x", "y", "yaw"});
               const nav::Pose2 pose = PoseOnMap(core_, body);
               sim.Teleport(pose);
               return JsonResponse(r, {{"pose", ToJson(pose)}});
             }));
  AddDoorRoutes(routes);
  AddLiftRoutes(routes);
}

void SimulatorApi::AddFaultRoutes(Router& routes) const {
  // Fault injection for the simulator: what the robot does when a device stops answering, or its own control loop
  // stalls (the systemd watchdog's test).
  routes.Add(http::verb::put, "/api/v1/sim/faults", Access::kOperator, Sync([this](const Request& r, const Params&) {
               drivers::sim::SimRobot& sim = Sim();
               const json body = ParseJsonBody(r);
               AllowOnlyKeys(body, {"camera_stopped", "control_stalled"}, "");
               for (const auto& [key, value] : body.items()) {
                 if (!value.is_boolean()) {
                   throw ApiError(http::status::bad_request, "Invalid faults", key + ": expected true or false");
                 }
               }
               if (body.contains("camera_stopped")) sim.SetCameraStopped(body["camera_stopped"].get<bool>());
               if (body.contains("control_stalled")) {
                 const bool stall = body["control_stalled"].get<bool>();
                 if (stall && !control_stalled_->exchange(true)) {
                   spdlog::warn("fault injected: the control loop stalls (for at most a minute)");
                   control_.Post([stalled = control_stalled_] {
                     const auto end = std::chrono::steady_clock::now() + std::chrono::minutes(1);
                     while (*stalled && std::chrono::steady_clock::now() < end) {
                       std::this_thread::sleep_for(std::chrono::milliseconds(10));
                     }
                     *stalled = false;
                   });
                 }
                 if (!stall) *control_stalled_ = false;
               }
               return JsonResponse(
                   r, {{"camera_stopped", sim.camera_stopped()}, {"control_stalled", control_stalled_->load()}});
             }));
}

void SimulatorApi::AddDoorRoutes(Router& routes) const {
  // The simulator's doors: what a building's door controller moves (it calls these as it would its door motors).
  routes.Add(http::verb::get, "/api/v1/sim/doors", Access::kViewer, Sync([this](const Request& r, const Params&) {
               json doors = json::array();
               for (const auto& [id, open] : Sim().doors()) doors.push_back({{"id", id}, {"open", open}});
               return JsonResponse(r, {{"doors", doors}});
             }));
  routes.Add(
      http::verb::put, "/api/v1/sim/doors/{id}", Access::kOperator, Sync([this](const Request& r, const Params& p) {
        drivers::sim::SimRobot& sim = Sim();
        const json body = ObjectBody(r, {"open"});
        if (!body.contains("open") || !body["open"].is_boolean()) {
          throw ApiError(http::status::bad_request, "Invalid request", "'open' must be true or false");
        }
        const std::string& id = p.at("id");
        if (!sim.SetDoorOpen(id, body["open"].get<bool>())) {
          throw ApiError(http::status::not_found, "No such door", "the simulator has no door '" + id + "'", "no_door");
        }
        return JsonResponse(r, {{"id", id}, {"open", body["open"]}});
      }));
}

void SimulatorApi::AddLiftRoutes(Router& routes) const {
  // The simulator's lifts: what a building's lift controller drives (it calls these as it would the lift's own
  // controls).
  const auto lift = [this](const std::string& id) {
    for (const drivers::sim::SimLiftState& l : Sim().lifts()) {
      if (l.id == id) return l;
    }
    throw ApiError(http::status::not_found, "No such lift", "the simulator has no lift '" + id + "'", "no_lift");
  };
  const auto lift_json = [](const drivers::sim::SimLiftState& l) {
    return json{
        {"id", l.id}, {"floor", l.floor}, {"destination", l.destination}, {"door", l.door_open ? "open" : "closed"}};
  };
  routes.Add(http::verb::get, "/api/v1/sim/lifts", Access::kViewer,
             Sync([this, lift_json](const Request& r, const Params&) {
               json lifts = json::array();
               for (const drivers::sim::SimLiftState& l : Sim().lifts()) lifts.push_back(lift_json(l));
               return JsonResponse(r, {{"lifts", std::move(lifts)}});
             }));
  routes.Add(http::verb::get, "/api/v1/sim/lifts/{id}", Access::kViewer,
             Sync([lift, lift_json](const Request& r, const Params& p) {
               return JsonResponse(r, lift_json(lift(p.at("id"))));
             }));
  routes.Add(http::verb::put, "/api/v1/sim/lifts/{id}", Access::kOperator,
             Sync([this, lift, lift_json](const Request& r, const Params& p) {
               const std::string& id = p.at("id");
               lift(id);
               const json body = ObjectBody(r, {"floor"});
               if (!body.contains("floor") || !body["floor"].is_string() || body["floor"].get<std::string>().empty()) {
                 throw ApiError(http::status::bad_request, "Invalid request", "'floor' must be the name of a floor");
               }
               const std::string floor = body["floor"].get<std::string>();
               if (!Sim().CallLift(id, floor)) {
                 throw ApiError(http::status::unprocessable_entity, "No such floor",
                                "lift '" + id + "' does not stop at floor '" + floor + "'", "unknown_floor");
               }
               return JsonResponse(r, lift_json(lift(id)));
             }));
  routes.Add(http::verb::post, "/api/v1/sim/lifts/{id}/release", Access::kOperator,
             Sync([this, lift, lift_json](const Request& r, const Params& p) {
               const std::string& id = p.at("id");
               lift(id);
               Sim().CallLift(id, "");
               return JsonResponse(r, lift_json(lift(id)));
             }));
}

}  // namespace corridor::server
