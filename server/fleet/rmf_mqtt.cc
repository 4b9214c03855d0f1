#include "server/fleet/rmf_mqtt.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace corridor::server {
namespace {

using json = nlohmann::json;

// rmf_door_msgs/DoorMode and rmf_lift_msgs constants.
constexpr int kDoorClosed = 0;
constexpr int kDoorOpen = 2;
constexpr int kDoorOffline = 3;
constexpr int kLiftEndSession = 0;
constexpr int kLiftAgvMode = 1;
constexpr int kLiftDoorClosed = 0;
constexpr int kLiftDoorOpen = 2;
constexpr int kLiftModeFire = 3;
constexpr int kLiftModeOffline = 4;
constexpr int kLiftModeEmergency = 5;

constexpr double kRepeatS = 2.0;

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// builtin_interfaces/Time now.
json Now() {
  const auto ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  return {{"sec", ns / 1000000000}, {"nanosec", ns % 1000000000}};
}

int IntAt(const json& j, const json::json_pointer& at, int fallback) {
  return j.contains(at) && j.at(at).is_number_integer() ? j.at(at).get<int>() : fallback;
}

std::string StringAt(const json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

}  // namespace

RmfStates::RmfStates(const RmfMqttOptions& options, const std::string& kind, const std::string& name_field)
    : options_(options),
      requests_topic_(options.prefix + "/" + kind + "_requests"),
      name_field_(name_field),
      link_(
          MqttLinkOptions{.broker = options.broker,
                          .client_id = options.requester_id + "-" + kind + "s",
                          .will = {},
                          .subscriptions = {options.prefix + "/" + kind + "_states"},
                          .subscription_qos = 1},
          [this](std::string, std::string payload) { OnMessage(payload); }, [] {}) {}

void RmfStates::OnMessage(const std::string& payload) {
  // On Paho's thread: a state that is not JSON, or names nothing, is dropped with a warning.
  try {
    json state = json::parse(payload);
    const std::string name = state.is_object() ? StringAt(state, name_field_.c_str()) : "";
    if (name.empty()) {
      spdlog::warn("rmf: a state without '{}' on {}: dropped", name_field_, options_.prefix);
      return;
    }
    std::lock_guard lock(mutex_);
    states_[name] = std::move(state);
  } catch (const json::exception& e) {
    spdlog::warn("rmf: a state that is not JSON: {}", e.what());
  }
}

void RmfStates::Request(const json& message) { link_.Publish({requests_topic_, message.dump(), 1, false}); }

std::optional<json> RmfStates::Latest(const std::string& name) const {
  std::lock_guard lock(mutex_);
  const auto it = states_.find(name);
  if (it == states_.end()) return std::nullopt;
  return it->second;
}

void RepeatedRequests::Set(const std::string& name, json request, double now_s) {
  requests_[name] = {std::move(request), now_s};
}

std::vector<json> RepeatedRequests::Due(double now_s, double repeat_s) {
  std::vector<json> due;
  for (auto& [name, request] : requests_) {
    if (now_s - request.second < repeat_s) continue;
    request.second = now_s;
    due.push_back(request.first);
  }
  return due;
}

RmfMqttDoorController::RmfMqttDoorController(const RmfMqttOptions& options) : states_(options, "door", "door_name") {}

void RmfMqttDoorController::Open(const std::string& door, Done done) {
  const json request = {{"time", Now()},
                        {"requester_id", states_.options().requester_id},
                        {"door_name", door},
                        {"requested_mode", {{"value", kDoorOpen}}}};
  states_.Request(request);
  requests_.Set(door, request, SteadySeconds());
  done({nav::DoorStatus::kOpening, ""});
}

void RmfMqttDoorController::Tick() {
  states_.Connect();
  for (json& request : requests_.Due(SteadySeconds(), kRepeatS)) {
    request["time"] = Now();
    states_.Request(request);
  }
}

void RmfMqttDoorController::State(const std::string& door, Done done) {
  const std::optional<json> state = states_.Latest(door);
  const int mode = state ? IntAt(*state, json::json_pointer("/current_mode/value"), -1) : -1;
  if (mode == kDoorOpen) return done({nav::DoorStatus::kOpen, ""});
  if (mode == kDoorOffline) return done({nav::DoorStatus::kRefused, "the door is offline"});
  done({nav::DoorStatus::kOpening, ""});
}

void RmfMqttDoorController::Release(const std::string& door) {
  requests_.Clear(door);
  states_.Request({{"time", Now()},
                   {"requester_id", states_.options().requester_id},
                   {"door_name", door},
                   {"requested_mode", {{"value", kDoorClosed}}}});
}

RmfMqttLiftController::RmfMqttLiftController(const RmfMqttOptions& options) : states_(options, "lift", "lift_name") {}

void RmfMqttLiftController::Call(const std::string& lift, const std::string& floor, Done done) {
  const json request = {{"lift_name", lift},
                        {"request_time", Now()},
                        {"session_id", states_.options().requester_id},
                        {"request_type", kLiftAgvMode},
                        {"destination_floor", floor},
                        {"door_state", kLiftDoorOpen}};
  states_.Request(request);
  requests_.Set(lift, request, SteadySeconds());
  done({});
}

void RmfMqttLiftController::Tick() {
  states_.Connect();
  for (json& request : requests_.Due(SteadySeconds(), kRepeatS)) {
    request["request_time"] = Now();
    states_.Request(request);
  }
}

void RmfMqttLiftController::State(const std::string& lift, Done done) {
  nav::LiftReport report;
  const std::optional<json> state = states_.Latest(lift);
  if (!state) return done(report);  // nothing heard yet: not there
  const int mode = IntAt(*state, json::json_pointer("/current_mode"), 0);
  if (mode == kLiftModeFire || mode == kLiftModeOffline || mode == kLiftModeEmergency) {
    report.refused = true;
    report.detail = mode == kLiftModeFire      ? "the lift is in fire mode"
                    : mode == kLiftModeOffline ? "the lift is offline"
                                               : "the lift is in emergency mode";
    return done(report);
  }
  // Only a car serving our session is there for the robot.
  if (StringAt(*state, "session_id") != states_.options().requester_id) return done(report);
  report.floor = StringAt(*state, "current_floor");
  report.door_open = IntAt(*state, json::json_pointer("/door_state"), kLiftDoorClosed) == kLiftDoorOpen;
  report.moving = IntAt(*state, json::json_pointer("/motion_state"), 0) != 0;
  done(report);
}

void RmfMqttLiftController::Release(const std::string& lift) {
  requests_.Clear(lift);
  states_.Request({{"lift_name", lift},
                   {"request_time", Now()},
                   {"session_id", states_.options().requester_id},
                   {"request_type", kLiftEndSession},
                   {"destination_floor", ""},
                   {"door_state", kLiftDoorClosed}});
}

}  // namespace corridor::server
