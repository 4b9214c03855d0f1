// The robot's side of VDA 5050 2.1's orders and instant actions, apart from MQTT (server/nodes/vda5050_node.h carries
// it): which orders and updates it takes (the standard's Figure 8), how their released nodes become a corridor mission
// (one goal per node, in order; an edge's maxSpeed limits the leg to its end node), how the mission's progress becomes
// nodeStates, edgeStates, lastNodeId and actionStates, and the order part of the state message. Rejections become
// errors as the standard names them (validationError, orderError, orderUpdateError, noOrderToCancel) with references.
//
// Actions this robot can carry out (the factsheet lists them): instant startPause, stopPause, cancelOrder,
// initPosition, stateRequest, factsheetRequest, startCharging (dock at the nearest dock) and stopCharging (back off
// it); on nodes startCharging (the node is reached by docking at the dock nearest it) and stopCharging; on nodes and
// edges "say" (this manufacturer's: parameter "text", spoken by the face). An order with any other action is refused.
//
// Pure logic: the caller hands in what arrives and the mission's progress, carries out the VdaCommands each call
// returns, and says which mission it started. Not thread-safe: one owner.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/geometry/pose2.h"
#include "nav/mission/docking.h"
#include "nav/mission/mission.h"
#include "server/runtime/fleet_order.h"

namespace corridor::server {

struct VdaAgentOptions {
  double default_deviation_m = 0.5;  // a node without allowedDeviationXY is reached within this
  nav::DockGeometry dock;            // for backing off a dock (stopCharging)
};

// What a call asks of the robot, in the order listed.
struct VdaCommands {
  std::string cancel;                                  // cancel this mission ("": none)
  std::optional<std::vector<nav::MissionGoal>> start;  // start a mission through these goals
  std::vector<nav::MissionGoal> extend;                // append these to the running mission (or start, if it ended)
  bool pause = false;
  bool resume = false;
  std::optional<nav::Pose2> set_pose;  // initPosition; its answer goes to PoseAnswered(set_pose_action, ...)
  std::string set_pose_action;
  std::vector<std::string> say;
  bool send_state = false;
  bool send_factsheet = false;
};

// The mission the agent drives, as the mission node reports it.
struct VdaMissionProgress {
  std::string id;
  nav::MissionStatus status = nav::MissionStatus::kActive;
  std::size_t current = 0;  // the goal under way (== goals when all are reached)
  std::size_t goals = 0;
  std::string error;
};

// What the agent needs to know of the robot when an order or an action arrives.
struct VdaRobotNow {
  std::optional<nav::Pose2> pose;  // map frame; none: not localized
  std::string map_id;
  bool docked = false;
  bool can_set_pose = false;  // localization takes a pose (initPosition)
};

class VdaAgent {
 public:
  // The docking goal for the dock nearest `near` on the active map, if there is one.
  using DockFinder = std::function<std::optional<nav::MissionGoal>(const nav::Pose2& near)>;

  VdaAgent(VdaAgentOptions options, DockFinder find_dock);

  // `order` has passed the schema (VdaSchemas::Check); what it asks is checked here.
  VdaCommands Order(const nlohmann::json& order, const VdaRobotNow& robot);
  VdaCommands InstantActions(const nlohmann::json& message, const VdaRobotNow& robot);
  // A message that failed the schema: validationError until an order is taken.
  void Invalid(const std::string& topic, const std::vector<std::string>& problems);
  // The mission the last VdaCommands started runs as `mission_id`, with `offset` goals put before the ones asked for
  // (backing off the dock first). An empty id: it could not start, for `error`.
  VdaCommands Started(const std::string& mission_id, std::size_t offset, const std::string& error = "");
  // The mission the last VdaCommands started was refused before anything moved (its goal for node `node_id` off the
  // map, in a wall or a keep-out zone, out of reach): the error `type` (validationError, noRouteError) names the order
  // and the node. A new order is not taken (the state shows the one before it); an update's new nodes wait for the
  // master control, as after any order it cannot drive.
  VdaCommands Refused(const std::string& type, const std::string& description, const std::string& node_id);
  // The running mission took the goals the last VdaCommands extended it with. (When it had just finished instead,
  // the caller reports its last Progress, then starts a mission with them and reports Started.)
  void Extended();
  // The robot core's answer to initPosition `action_id`: taken (`refusal` empty) or refused, saying why.
  VdaCommands PoseAnswered(const std::string& action_id, const std::string& refusal);
  VdaCommands Progress(const VdaMissionProgress& progress);
  // Paused by startPause (a mission it starts is paused at once).
  bool paused() const { return paused_; }

  // The state's order part: orderId, orderUpdateId, lastNodeId, lastNodeSequenceId, nodeStates, edgeStates,
  // actionStates; and these errors appended to `errors`.
  // Marks the order part sent (changed() is false until something changes again).
  void FillState(nlohmann::json& state);
  // Something in the order part changed since the last FillState: the state should go out now.
  bool changed() const { return changed_; }
  // The actions the factsheet lists (protocolFeatures.agvActions).
  static nlohmann::json FactsheetActions();

  // The order as a map shows it (protocol, connection and stamp left to the caller).
  FleetOrder Describe() const;

  bool has_order() const { return !order_id_.empty(); }
  // The mission driving the order (or an instant charging action); "" when none.
  const std::string& mission_id() const { return mission_id_; }
  // Nodes still to traverse or actions neither finished nor failed: an order is under way.
  bool Busy() const;

 private:
  struct Action {
    std::string type;
    std::string id;
    std::string blocking;
    nlohmann::json parameters = nlohmann::json::array();
    std::string status = "WAITING";
    std::string result;
  };
  struct Node {
    std::string id;
    std::uint32_t sequence = 0;
    bool released = false;
    nlohmann::json position;  // as sent (null: none)
    std::vector<std::string> actions;
  };
  struct Edge {
    std::string id;
    std::uint32_t sequence = 0;
    bool released = false;
    std::string start;
    std::string end;
    std::optional<double> max_speed;
    std::vector<std::string> actions;
  };
  struct Error {
    std::string type;
    std::string level;
    std::string description;
    std::vector<std::pair<std::string, std::string>> references;
  };
  // What mission goals are for.
  struct GoalFor {
    std::size_t node_sequence = 0;
    std::string action_id;  // a stopCharging node action's undocking goal
  };

  void Reject(std::string type, std::string description, std::vector<std::pair<std::string, std::string>> refs);
  // The order's problems as orderError references; empty when it can be carried out.
  std::optional<Error> Unusable(const nlohmann::json& order) const;
  void Take(const nlohmann::json& order, bool update);
  // Goals for the released nodes not yet handed to a mission, appended to `goals` (and batch_).
  void NewGoals(std::vector<nav::MissionGoal>& goals);
  // Hands the new goals over: extends the running mission, or starts one.
  void Drive(std::vector<nav::MissionGoal> goals, VdaCommands& commands);
  // Node `sequence` is reached: its state goes, its actions run, the edge after it is entered.
  void Traverse(std::uint32_t sequence, VdaCommands& commands);
  Action* FindAction(const std::string& id);
  void SetStatus(Action& action, std::string status, std::string result = "");
  void FailOpenActions(const std::string& why);
  void RunInstant(const nlohmann::json& action, const VdaRobotNow& robot, VdaCommands& commands);
  static std::string Param(const Action& action, const std::string& key);
  static Action MakeAction(const nlohmann::json& action);  // from an order's or instantActions' action

  VdaAgentOptions options_;
  DockFinder find_dock_;
  std::string order_id_;
  std::uint32_t order_update_id_ = 0;
  std::string last_node_id_;
  std::uint32_t last_node_sequence_ = 0;
  nlohmann::json last_node_position_;  // null: not known (none yet, or set by initPosition)
  std::vector<Node> nodes_;            // still to traverse, base then horizon
  std::vector<Edge> edges_;
  std::vector<Action> actions_;  // of the order and the instant actions since it was taken
  std::vector<Error> errors_;
  std::optional<std::uint32_t> handed_through_;  // the last node handed to the mission (its sequenceId)
  std::string mission_id_;
  std::vector<std::string> started_;  // the missions the agent started lately (a late word of one is not news)
  std::size_t offset_ = 0;
  std::vector<GoalFor> goals_for_;      // per goal of the running mission the agent asked for, in order
  std::vector<GoalFor> batch_;          // per goal of the last start or extension, until it is confirmed
  std::size_t reached_ = 0;             // goals reached so far
  std::string instant_mission_action_;  // an instant startCharging/stopCharging under way
  // The order before the last new one was taken, until the mission that drives it starts: a refusal puts it back.
  std::optional<std::pair<std::string, std::uint32_t>> order_before_;
  bool paused_ = false;
  bool changed_ = true;
};

}  // namespace corridor::server
