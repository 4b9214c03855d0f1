// VDA 5050 2.1 over MQTT: a master control's orders and instant actions drive the robot through the mission node, and
// the robot reports its state (at least every state_interval_s and on every change), its visualization, its
// factsheet and its connection (ONLINE; OFFLINE at shutdown; CONNECTIONBROKEN as the broker's last will). The order
// logic is server/fleet/vda5050_agent.h, the messages server/fleet/vda5050.h, the connection server/fleet/mqtt_link.h;
// this node wires them to the bus. Every message in and out is checked against the standard's schemas: one that
// arrives invalid is reported as a validationError and not used; one the robot would send invalid is logged and not
// sent. Runs on the io executor.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/fleet/mqtt_link.h"
#include "server/fleet/vda5050.h"
#include "server/fleet/vda5050_agent.h"
#include "server/nodes/mission_node.h"
#include "server/runtime/node.h"
#include "server/store/map_library.h"

namespace corridor::server {

class Vda5050Node final : public PeriodicNode {
 public:
  // `robot_name` is the serial number when the options give none. Throws std::invalid_argument for a broker address
  // that is not an MQTT URL.
  // Missions start, extend, pause, resume and cancel through `core` (an order or an update with a node the core
  // refuses is refused on arrival), which also gives the state, a mission's progress and the dock to go to.
  Vda5050Node(Executor& io, Bus& bus, const Config& config, const RobotCore& core, std::string robot_name);
  void Activate() override;
  void Deactivate() override;

 private:
  void Tick() override;
  // From Paho's threads, posted here.
  void Received(const std::string& topic, const std::string& payload);
  void Connected();
  void OnMission(const MissionState& mission);
  // Carries out what the agent asked.
  void Carry(VdaCommands commands);
  // Asks the core for a mission through `goals` (the agent's, each for a node); the agent hears, on this executor,
  // that it started or was refused.
  void StartMission(std::vector<nav::MissionGoal> goals);
  // An order update's goals onto the running mission, through the core (checked as a new order's are).
  void ExtendMission(std::vector<nav::MissionGoal> goals);
  // The core refused goals for `nodes` (each goal's node): the order's error names the node.
  void Refused(const nav::MissionRefusal& refusal, const std::vector<std::string>& nodes);
  // initPosition through the core; its answer finishes or fails action `action_id`.
  void SetPose(const nav::Pose2& pose, const std::string& action_id);
  void Answered(const MissionResult& result, const std::vector<std::string>& nodes, std::size_t asked);
  VdaRobot Sample();
  VdaRobotNow Now();
  void SendState();  // with the robot sampled now
  void SendState(const VdaRobot& robot);
  // The order and the connection, for the console (topics::kFleetOrder).
  void PublishOrder();
  void Send(VdaMessage kind, nlohmann::json message, bool retained = false);
  VdaHeader NextHeader(VdaMessage kind);

  const Vda5050Options options_;
  const Config& config_;
  VdaIdentity identity_;
  const RobotCore& core_;
  VdaSchemas schemas_;
  VdaAgent agent_;
  VdaVehicle vehicle_;
  LoopStats& sent_;  // one loop per message handed to the broker (the publish call's own time)
  std::unique_ptr<MqttLink> link_;
  std::map<VdaMessage, std::uint32_t> header_ids_;
  double last_state_s_ = -1e300;
  std::string last_state_key_;  // what of the robot the last state said that counts as a change
  bool shown_connected_ = false;
};

}  // namespace corridor::server
