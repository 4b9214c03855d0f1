// Door and lift controllers that speak Open-RMF's door and lift messages (rmf_door_msgs, rmf_lift_msgs), as JSON with
// the messages' field names, over MQTT: what a building whose doors and lifts already serve an RMF deployment offers
// through an MQTT bridge. The robot publishes DoorRequest on PREFIX/door_requests and LiftRequest on
// PREFIX/lift_requests, and reads DoorState from PREFIX/door_states and LiftState from PREFIX/lift_states.
//
// The semantics are RMF's: a door is open when its DoorState says MODE_OPEN, and offline (MODE_OFFLINE) is a
// refusal; a lift serves the robot in a session (session_id = requester_id, request_type AGV_MODE) and is there when
// its LiftState has our session, current_floor the floor asked for and DOOR_OPEN; fire, emergency and offline modes
// are refusals; releasing ends the session (REQUEST_END_SESSION) or asks the door closed.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/config/config.h"
#include "server/fleet/doors.h"
#include "server/fleet/lifts.h"
#include "server/fleet/mqtt_link.h"

namespace corridor::server {

// The latest state message of each door or lift on one topic, by its name field; requests go out on another.
class RmfStates {
 public:
  // Throws std::invalid_argument for a broker address that is not an MQTT URL.
  RmfStates(const RmfMqttOptions& options, const std::string& kind, const std::string& name_field);
  // Connects until the first connection (MqttLink::Connect).
  void Connect() { link_.Connect(); }
  void Request(const nlohmann::json& message);
  std::optional<nlohmann::json> Latest(const std::string& name) const;
  const RmfMqttOptions& options() const { return options_; }

 private:
  void OnMessage(const std::string& payload);

  RmfMqttOptions options_;
  std::string requests_topic_;
  std::string name_field_;
  mutable std::mutex mutex_;
  std::map<std::string, nlohmann::json> states_;  // guarded by mutex_
  MqttLink link_;
};

// The requests in force (a door asked open, a lift called), sent again every repeat_s as RMF's own adapters do, so
// that a request a door or lift adapter missed (it restarted, say) is not lost. Not thread-safe: the node's executor.
class RepeatedRequests {
 public:
  void Set(const std::string& name, nlohmann::json request, double now_s);
  void Clear(const std::string& name) { requests_.erase(name); }
  // The requests due again at now_s.
  std::vector<nlohmann::json> Due(double now_s, double repeat_s);

 private:
  std::map<std::string, std::pair<nlohmann::json, double>> requests_;  // name -> request, when last sent
};

class RmfMqttDoorController final : public DoorController {
 public:
  explicit RmfMqttDoorController(const RmfMqttOptions& options);
  void Open(const std::string& door, Done done) override;
  void State(const std::string& door, Done done) override;
  void Release(const std::string& door) override;
  void Tick() override;

 private:
  RmfStates states_;
  RepeatedRequests requests_;
};

class RmfMqttLiftController final : public LiftController {
 public:
  explicit RmfMqttLiftController(const RmfMqttOptions& options);
  void Call(const std::string& lift, const std::string& floor, Done done) override;
  void State(const std::string& lift, Done done) override;
  void Release(const std::string& lift) override;
  void Tick() override;

 private:
  RmfStates states_;
  RepeatedRequests requests_;
};

}  // namespace corridor::server
