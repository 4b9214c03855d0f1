#include "server/fleet/vda5050_agent.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace corridor::server {
namespace {

using json = nlohmann::json;

constexpr const char* kWaiting = "WAITING";
constexpr const char* kRunning = "RUNNING";
constexpr const char* kFinished = "FINISHED";
constexpr const char* kFailed = "FAILED";
constexpr std::size_t kMaxSayChars = 200;

bool Open(const std::string& status) { return status != kFinished && status != kFailed; }

struct Supported {
  const char* type;
  bool instant, node, edge;
  const char* description;
};
constexpr Supported kActions[] = {
    {"startPause", true, false, false, "stop driving; the order is kept"},
    {"stopPause", true, false, false, "drive on"},
    {"cancelOrder", true, false, false, "stop at once and drop the order"},
    {"initPosition", true, false, false, "set the robot's pose (x, y, theta on mapId)"},
    {"stateRequest", true, false, false, "send the state now"},
    {"factsheetRequest", true, false, false, "send the factsheet"},
    {"startCharging", true, true, false, "dock at the nearest dock (on a node: the dock nearest the node)"},
    {"stopCharging", true, true, false, "back off the dock"},
    {"say", true, true, true, "say a phrase (parameter text) on the robot's speaker"},
};

const Supported* FindSupported(const std::string& type) {
  for (const Supported& s : kActions) {
    if (type == s.type) return &s;
  }
  return nullptr;
}

double Number(const json& object, const char* key, double otherwise) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number() ? it->get<double>() : otherwise;
}

}  // namespace

VdaAgent::VdaAgent(VdaAgentOptions options, DockFinder find_dock)
    : options_(std::move(options)), find_dock_(std::move(find_dock)) {}

json VdaAgent::FactsheetActions() {
  json out = json::array();
  for (const Supported& s : kActions) {
    json scopes = json::array();
    if (s.instant) scopes.push_back("INSTANT");
    if (s.node) scopes.push_back("NODE");
    if (s.edge) scopes.push_back("EDGE");
    json action = {{"actionType", s.type}, {"actionScopes", scopes}, {"actionDescription", s.description}};
    if (std::string(s.type) == "say") {
      action["actionParameters"] = {{{"key", "text"}, {"valueDataType", "STRING"}, {"isOptional", false}}};
    } else if (std::string(s.type) == "initPosition") {
      json params = json::array();
      for (const char* key : {"x", "y", "theta"}) params.push_back({{"key", key}, {"valueDataType", "NUMBER"}});
      params.push_back({{"key", "mapId"}, {"valueDataType", "STRING"}});
      params.push_back({{"key", "lastNodeId"}, {"valueDataType", "STRING"}, {"isOptional", true}});
      action["actionParameters"] = std::move(params);
    }
    out.push_back(std::move(action));
  }
  return out;
}

bool VdaAgent::Busy() const {
  if (!nodes_.empty()) return true;
  return std::any_of(actions_.begin(), actions_.end(), [](const Action& a) { return Open(a.status); });
}

void VdaAgent::Reject(std::string type, std::string description,
                      std::vector<std::pair<std::string, std::string>> refs) {
  errors_.push_back({std::move(type), "WARNING", std::move(description), std::move(refs)});
  changed_ = true;
}

void VdaAgent::Invalid(const std::string& topic, const std::vector<std::string>& problems) {
  std::string description = topic + " does not follow the schema";
  for (std::size_t i = 0; i < problems.size() && i < 3; ++i) description += (i ? "; " : ": ") + problems[i];
  Reject("validationError", std::move(description), {{"topic", topic}});
}

std::string VdaAgent::Param(const Action& action, const std::string& key) {
  for (const json& p : action.parameters) {
    if (p.value("key", "") != key) continue;
    const json& value = p["value"];
    return value.is_string() ? value.get<std::string>() : value.dump();
  }
  return "";
}

VdaAgent::Action VdaAgent::MakeAction(const json& action) {
  Action a;
  a.type = action["actionType"];
  a.id = action["actionId"];
  a.blocking = action["blockingType"];
  a.parameters = action.value("actionParameters", json::array());
  return a;
}

VdaAgent::Action* VdaAgent::FindAction(const std::string& id) {
  for (Action& a : actions_) {
    if (a.id == id) return &a;
  }
  return nullptr;
}

void VdaAgent::SetStatus(Action& action, std::string status, std::string result) {
  if (action.status == status && action.result == result) return;
  action.status = std::move(status);
  action.result = std::move(result);
  changed_ = true;
}

void VdaAgent::FailOpenActions(const std::string& why) {
  for (Action& a : actions_) {
    if (Open(a.status)) SetStatus(a, kFailed, why);
  }
}

// What an order asks that this robot cannot do, as orderError's references (6.6.4.2); nullopt when it can.
std::optional<VdaAgent::Error> VdaAgent::Unusable(const json& order) const {
  const json& nodes = order["nodes"];
  const json& edges = order["edges"];
  auto error = [](std::string description, std::string key, std::string value) {
    return Error{"orderError", "WARNING", std::move(description), {{std::move(key), std::move(value)}}};
  };
  if (nodes.empty()) return error("an order needs at least one node", "nodes", "[]");
  if (edges.size() + 1 != nodes.size()) {
    return error("an order has one edge fewer than nodes", "edges", std::to_string(edges.size()));
  }
  bool horizon = false;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const json& node = nodes[i];
    const std::string id = node["nodeId"];
    if (i > 0) {
      const json& edge = edges[i - 1];
      if (edge["startNodeId"] != nodes[i - 1]["nodeId"] || edge["endNodeId"] != node["nodeId"]) {
        return error("edge " + edge["edgeId"].get<std::string>() + " does not join nodes " + std::to_string(i - 1) +
                         " and " + std::to_string(i),
                     "edgeId", edge["edgeId"]);
      }
      if (edge["released"].get<bool>() && !node["released"].get<bool>()) {
        return error("a released edge ends at a node that is not", "edgeId", edge["edgeId"]);
      }
      if (edge.contains("trajectory"))
        return error("this robot plans its own way: no trajectory", "edgeId", edge["edgeId"]);
      for (const json& a : edge["actions"]) {
        const Supported* s = FindSupported(a["actionType"]);
        if (s == nullptr || !s->edge) {
          return error("action " + a["actionType"].get<std::string>() + " cannot be done on an edge", "actionId",
                       a["actionId"]);
        }
      }
    }
    if (!node["released"].get<bool>()) horizon = true;
    if (node["released"].get<bool>() && horizon) return error("a released node follows the horizon", "nodeId", id);
    if (!node.contains("nodePosition")) return error("this robot needs every node's position", "nodeId", id);
    for (const json& a : node["actions"]) {
      const std::string type = a["actionType"];
      const Supported* s = FindSupported(type);
      if (s == nullptr || !s->node)
        return error("action " + type + " cannot be done on a node", "actionId", a["actionId"]);
      if (type == "startCharging") {
        const json& p = node["nodePosition"];
        if (!find_dock_ || !find_dock_(nav::Pose2{p["x"], p["y"], 0.0})) {
          return error("there is no dock to charge at near node " + id, "nodeId", id);
        }
      }
    }
  }
  // Every action's text, where it says something.
  auto check_say = [&](const json& actions) -> std::optional<Error> {
    for (const json& a : actions) {
      if (a["actionType"] != "say") continue;
      const std::string text = Param(MakeAction(a), "text");
      if (text.empty() || text.size() > kMaxSayChars) {
        return error("say needs a text of 1 to 200 characters", "actionId", a["actionId"]);
      }
    }
    return std::nullopt;
  };
  for (const json& n : nodes) {
    if (auto e = check_say(n["actions"])) return e;
  }
  for (const json& e : edges) {
    if (auto bad = check_say(e["actions"])) return bad;
  }
  return std::nullopt;
}

void VdaAgent::Take(const json& order, bool update) {
  // The base cannot change: an update replaces only the horizon, from the stitching node on.
  if (update) {
    nodes_.erase(std::remove_if(nodes_.begin(), nodes_.end(), [](const Node& n) { return !n.released; }), nodes_.end());
    edges_.erase(std::remove_if(edges_.begin(), edges_.end(), [](const Edge& e) { return !e.released; }), edges_.end());
  } else {
    nodes_.clear();
    edges_.clear();
    actions_.erase(std::remove_if(actions_.begin(), actions_.end(), [](const Action& a) { return !Open(a.status); }),
                   actions_.end());
    handed_through_.reset();
    mission_id_.clear();
    goals_for_.clear();
    reached_ = 0;
  }
  errors_.clear();  // rejections are reported until an order is taken
  order_id_ = order["orderId"];
  order_update_id_ = order["orderUpdateId"];
  auto take_actions = [&](const json& actions) {
    std::vector<std::string> ids;
    for (const json& a : actions) {
      actions_.push_back(MakeAction(a));
      ids.push_back(a["actionId"]);
    }
    return ids;
  };
  const json& nodes = order["nodes"];
  const json& edges = order["edges"];
  for (std::size_t i = update ? 1 : 0; i < nodes.size(); ++i) {
    const json& n = nodes[i];
    nodes_.push_back({n["nodeId"], n["sequenceId"], n["released"], n["nodePosition"], take_actions(n["actions"])});
  }
  for (const json& e : edges) {
    std::optional<double> max_speed;
    if (e.contains("maxSpeed")) max_speed = e["maxSpeed"].get<double>();
    edges_.push_back({e["edgeId"], e["sequenceId"], e["released"], e["startNodeId"], e["endNodeId"], max_speed,
                      take_actions(e["actions"])});
  }
  changed_ = true;
}

VdaCommands VdaAgent::Order(const json& order, const VdaRobotNow& robot) {
  VdaCommands commands;
  commands.send_state = true;  // receiving an order is an event the state reports
  const std::string order_id = order["orderId"];
  const std::uint32_t update_id = order["orderUpdateId"];
  const json& nodes = order["nodes"];
  if (auto unusable = Unusable(order)) {
    errors_.push_back(std::move(*unusable));
    changed_ = true;
    return commands;
  }
  for (const json& n : nodes) {
    if (n["nodePosition"]["mapId"] != robot.map_id) {
      Reject("orderError",
             "node " + n["nodeId"].get<std::string>() + " is on map " + n["nodePosition"]["mapId"].get<std::string>() +
                 ", the robot on " + robot.map_id,
             {{"nodeId", n["nodeId"]}});
      return commands;
    }
  }
  const std::string first_id = nodes[0]["nodeId"];
  const std::uint32_t first_sequence = nodes[0]["sequenceId"];
  if (order_id != order_id_) {
    if (Busy()) {
      Reject("orderUpdateError", "order " + order_id_ + " is still under way; cancel it first",
             {{"orderId", order_id}});
      return commands;
    }
    // The first node must be where the robot is (within its deviation range).
    const json& p = nodes[0]["nodePosition"];
    const double allowed = Number(p, "allowedDeviationXY", 0.0) > 0.0 ? p["allowedDeviationXY"].get<double>()
                                                                      : options_.default_deviation_m;
    if (!robot.pose ||
        std::hypot(robot.pose->x_m - p["x"].get<double>(), robot.pose->y_m - p["y"].get<double>()) > allowed) {
      Reject(
          "orderError",
          robot.pose ? "the robot is not at the order's first node " + first_id : "the robot does not know where it is",
          {{"nodeId", first_id}});
      return commands;
    }
    order_before_ = std::pair(order_id_, order_update_id_);
    Take(order, false);
    std::vector<nav::MissionGoal> goals;
    if (const Node first = nodes_.front(); first.released) {
      handed_through_ = first.sequence;
      Traverse(first.sequence, commands);
      // Charging stops where the robot stands: backing off the dock first, if it is on one.
      for (const std::string& id : first.actions) {
        Action* a = FindAction(id);
        if (a == nullptr || a->type != "stopCharging") continue;
        if (!robot.docked) {
          SetStatus(*a, kFinished);
        } else if (goals.empty()) {
          goals.push_back(nav::UndockGoal(robot.pose, options_.dock));
          batch_.push_back({first.sequence, id});
        }
      }
    }
    Drive(std::move(goals), commands);
    if (!commands.start) order_before_.reset();  // taken: nothing to drive yet, nothing to refuse
    return commands;
  }
  if (update_id < order_update_id_) {
    Reject("orderUpdateError",
           "update " + std::to_string(update_id) + " is older than " + std::to_string(order_update_id_),
           {{"orderId", order_id}, {"orderUpdateId", std::to_string(update_id)}});
    return commands;
  }
  if (update_id == order_update_id_) {
    commands.send_state = false;  // the same update again: ignored
    return commands;
  }
  // An update stitches onto the decision point: the base's last node, or the last node traversed.
  std::string stitch_id = last_node_id_;
  std::uint32_t stitch_sequence = last_node_sequence_;
  for (const Node& n : nodes_) {
    if (!n.released) break;
    stitch_id = n.id;
    stitch_sequence = n.sequence;
  }
  if (first_id != stitch_id || first_sequence != stitch_sequence) {
    Reject("orderUpdateError",
           "the update starts at " + first_id + "/" + std::to_string(first_sequence) + ", not at the decision point " +
               stitch_id + "/" + std::to_string(stitch_sequence),
           {{"orderId", order_id}, {"nodeId", first_id}});
    return commands;
  }
  Take(order, true);
  Drive({}, commands);
  return commands;
}

void VdaAgent::NewGoals(std::vector<nav::MissionGoal>& goals) {
  for (const Node& node : nodes_) {
    if (!node.released) break;
    // The edge leading to this node limits the leg.
    double edge_speed = std::numeric_limits<double>::infinity();
    for (const Edge& e : edges_) {
      if (e.sequence + 1 == node.sequence && e.max_speed) edge_speed = *e.max_speed;
    }
    if (handed_through_ && node.sequence <= *handed_through_) continue;
    handed_through_ = node.sequence;
    const json& p = node.position;
    nav::MissionGoal goal;
    goal.pose = {p["x"].get<double>(), p["y"].get<double>(), Number(p, "theta", 0.0)};
    goal.has_yaw = p.contains("theta");
    goal.place = node.id;
    goal.max_speed_mps = edge_speed;
    std::string undock_action;
    for (const std::string& id : node.actions) {
      const Action* a = FindAction(id);
      if (a == nullptr) continue;
      if (a->type == "startCharging") {
        if (auto dock = find_dock_(goal.pose)) {
          dock->place = node.id;
          dock->max_speed_mps = goal.max_speed_mps;
          goal = *dock;
        }
      } else if (a->type == "stopCharging") {
        undock_action = id;
      }
    }
    goals.push_back(goal);
    batch_.push_back({node.sequence, ""});
    if (!undock_action.empty()) {
      goals.push_back(nav::UndockGoal(goal.action == nav::GoalAction::kDock ? goal.dock : goal.pose, options_.dock));
      batch_.push_back({node.sequence, undock_action});
    }
  }
}

void VdaAgent::Drive(std::vector<nav::MissionGoal> goals, VdaCommands& commands) {
  NewGoals(goals);
  if (goals.empty()) return;
  if (!mission_id_.empty()) {
    commands.extend = std::move(goals);
    return;
  }
  commands.start = std::move(goals);
  if (paused_) commands.pause = true;
}

void VdaAgent::Traverse(std::uint32_t sequence, VdaCommands& commands) {
  const auto node = std::find_if(nodes_.begin(), nodes_.end(), [&](const Node& n) { return n.sequence == sequence; });
  if (node == nodes_.end()) return;
  last_node_id_ = node->id;
  last_node_sequence_ = node->sequence;
  last_node_position_ = node->position;
  // Leaving the edge that led here: its actions are over.
  for (auto e = edges_.begin(); e != edges_.end();) {
    if (e->sequence >= sequence) {
      ++e;
      continue;
    }
    for (const std::string& id : e->actions) {
      if (Action* a = FindAction(id); a != nullptr && Open(a->status)) SetStatus(*a, kFinished);
    }
    e = edges_.erase(e);
  }
  for (const std::string& id : node->actions) {
    Action* a = FindAction(id);
    if (a == nullptr) continue;
    if (a->type == "say") {
      commands.say.push_back(Param(*a, "text"));
      SetStatus(*a, kFinished);
    } else if (a->type == "startCharging") {
      SetStatus(*a, kFinished);  // the node was reached by docking
    } else if (a->type == "stopCharging") {
      SetStatus(*a, kRunning);  // its undocking goal follows
    }
  }
  nodes_.erase(node);
  // Entering the edge after it: its actions begin.
  for (Edge& e : edges_) {
    if (e.sequence != sequence + 1 || !e.released) continue;
    for (const std::string& id : e.actions) {
      Action* a = FindAction(id);
      if (a == nullptr || a->status != kWaiting) continue;
      if (a->type == "say") commands.say.push_back(Param(*a, "text"));
      SetStatus(*a, a->type == "say" ? kFinished : kRunning);
    }
  }
  changed_ = true;
  commands.send_state = true;
}

VdaCommands VdaAgent::Started(const std::string& mission_id, std::size_t offset, const std::string& error) {
  order_before_.reset();
  VdaCommands commands;
  commands.send_state = true;
  if (!mission_id.empty()) {
    started_.push_back(mission_id);
    if (started_.size() > 16) started_.erase(started_.begin());
  }
  std::vector<GoalFor> batch = std::move(batch_);
  batch_.clear();
  if (!instant_mission_action_.empty()) {
    if (mission_id.empty()) {
      if (Action* a = FindAction(instant_mission_action_)) SetStatus(*a, kFailed, error);
      instant_mission_action_.clear();
    }
    mission_id_ = mission_id;
    offset_ = offset;
    return commands;
  }
  if (mission_id.empty()) {
    // Nothing moves: the order waits for the master control (cancel, or an update handing the nodes again).
    Reject("orderError", "the robot cannot drive this order: " + error, {{"orderId", order_id_}});
    for (const GoalFor& g : batch) {
      if (Action* a = FindAction(g.action_id); a != nullptr && Open(a->status)) SetStatus(*a, kFailed, error);
    }
    handed_through_.reset();
    if (!last_node_id_.empty()) handed_through_ = last_node_sequence_;
    return commands;
  }
  mission_id_ = mission_id;
  offset_ = offset;
  goals_for_ = std::move(batch);
  reached_ = 0;
  return commands;
}

VdaCommands VdaAgent::Refused(const std::string& type, const std::string& description, const std::string& node_id) {
  VdaCommands commands;
  commands.send_state = true;
  std::vector<GoalFor> batch = std::move(batch_);
  batch_.clear();
  if (!instant_mission_action_.empty()) {
    if (Action* a = FindAction(instant_mission_action_)) SetStatus(*a, kFailed, description);
    instant_mission_action_.clear();
    return commands;
  }
  const std::string refused = order_id_;
  if (order_before_) {
    // Not taken: its nodes, edges and actions go, and the order before it stands.
    const auto drop_actions = [&](const std::vector<std::string>& ids) {
      actions_.erase(
          std::remove_if(actions_.begin(), actions_.end(),
                         [&](const Action& a) { return std::find(ids.begin(), ids.end(), a.id) != ids.end(); }),
          actions_.end());
    };
    for (const Node& n : nodes_) drop_actions(n.actions);
    for (const Edge& e : edges_) drop_actions(e.actions);
    nodes_.clear();
    edges_.clear();
    handed_through_.reset();
    std::tie(order_id_, order_update_id_) = *order_before_;
    order_before_.reset();
  } else {
    for (const GoalFor& g : batch) {
      if (Action* a = FindAction(g.action_id); a != nullptr && Open(a->status)) SetStatus(*a, kFailed, description);
    }
    handed_through_.reset();
    if (!last_node_id_.empty()) handed_through_ = last_node_sequence_;
  }
  Reject(type, description, {{"orderId", refused}, {"nodeId", node_id}});
  return commands;
}

void VdaAgent::Extended() {
  goals_for_.insert(goals_for_.end(), batch_.begin(), batch_.end());
  batch_.clear();
}

VdaCommands VdaAgent::Progress(const VdaMissionProgress& progress) {
  VdaCommands commands;
  if (progress.id.empty() || mission_id_.empty()) return commands;
  if (progress.id != mission_id_) {
    // A late word of a mission the agent started before: nothing new.
    if (std::find(started_.begin(), started_.end(), progress.id) != started_.end()) return commands;
    // Someone else (the console, the REST API) started a mission: the order's was cancelled by it.
    return Progress({mission_id_, nav::MissionStatus::kCanceled, offset_ + reached_, 0, "replaced by another mission"});
  }
  const bool succeeded = progress.status == nav::MissionStatus::kSucceeded;
  const bool finished =
      succeeded || progress.status == nav::MissionStatus::kFailed || progress.status == nav::MissionStatus::kCanceled;
  if (!instant_mission_action_.empty()) {
    if (!finished) return commands;
    if (Action* a = FindAction(instant_mission_action_)) {
      SetStatus(*a, succeeded ? kFinished : kFailed, succeeded ? "" : progress.error);
    }
    instant_mission_action_.clear();
    mission_id_.clear();
    commands.send_state = true;
    return commands;
  }
  const std::size_t done = succeeded ? progress.goals : progress.current;
  const std::size_t ours = done > offset_ ? std::min(done - offset_, goals_for_.size()) : 0;
  for (; reached_ < ours; ++reached_) {
    const GoalFor& goal = goals_for_[reached_];
    if (goal.action_id.empty()) {
      Traverse(goal.node_sequence, commands);
    } else if (Action* a = FindAction(goal.action_id)) {
      SetStatus(*a, kFinished);
      commands.send_state = true;
    }
  }
  if (finished) {
    if (!succeeded) {
      const std::string why =
          progress.status == nav::MissionStatus::kCanceled ? "the mission was cancelled" : progress.error;
      Reject("navigationError",
             "the robot stopped short of node " + (nodes_.empty() ? std::string("?") : nodes_.front().id) + ": " + why,
             {{"orderId", order_id_}});
      for (const GoalFor& g : goals_for_) {
        if (Action* a = FindAction(g.action_id); a != nullptr && Open(a->status)) SetStatus(*a, kFailed, why);
      }
      // An update can hand the nodes left to a new mission.
      handed_through_.reset();
      if (!last_node_id_.empty()) handed_through_ = last_node_sequence_;
      commands.send_state = true;
    }
    mission_id_.clear();
    goals_for_.clear();
    reached_ = 0;
  }
  return commands;
}

void VdaAgent::RunInstant(const json& message, const VdaRobotNow& robot, VdaCommands& commands) {
  const std::string type = message["actionType"];
  const std::string id = message["actionId"];
  actions_.push_back(MakeAction(message));
  Action& action = actions_.back();
  changed_ = true;
  commands.send_state = true;
  const Supported* supported = FindSupported(type);
  auto fail = [&](std::string error_type, std::string why) {
    SetStatus(action, kFailed, why);
    Reject(std::move(error_type), type + ": " + why, {{"actionId", id}, {"actionType", type}});
  };
  if (supported == nullptr || !supported->instant) return fail("actionError", "not an action this robot can do");
  if (type == "startPause" || type == "stopPause") {
    paused_ = type == "startPause";
    if (!mission_id_.empty()) (paused_ ? commands.pause : commands.resume) = true;
    SetStatus(action, kFinished);
  } else if (type == "cancelOrder") {
    if (nodes_.empty() && mission_id_.empty()) return fail("noOrderToCancel", "there is no order to cancel");
    commands.cancel = mission_id_;
    mission_id_.clear();
    goals_for_.clear();
    reached_ = 0;
    nodes_.clear();
    edges_.clear();
    instant_mission_action_.clear();
    for (Action& a : actions_) {
      if (&a != &action && Open(a.status)) SetStatus(a, kFailed, "the order was cancelled");
    }
    SetStatus(action, kFinished);
  } else if (type == "stateRequest") {
    SetStatus(action, kFinished);
  } else if (type == "factsheetRequest") {
    commands.send_factsheet = true;
    SetStatus(action, kFinished);
  } else if (type == "say") {
    const std::string text = Param(action, "text");
    if (text.empty() || text.size() > kMaxSayChars) return fail("actionError", "needs a text of 1 to 200 characters");
    commands.say.push_back(text);
    SetStatus(action, kFinished);
  } else if (type == "initPosition") {
    double value[3];
    const char* keys[] = {"x", "y", "theta"};
    for (int i = 0; i < 3; ++i) {
      const std::string text = Param(action, keys[i]);
      char* end = nullptr;
      value[i] = text.empty() ? NAN : std::strtod(text.c_str(), &end);
      if (!std::isfinite(value[i]) || end == nullptr || *end != '\0') {
        return fail("actionError", std::string("needs a number ") + keys[i]);
      }
    }
    if (Param(action, "mapId") != robot.map_id) return fail("actionError", "the robot is on map " + robot.map_id);
    if (!robot.can_set_pose) return fail("actionError", "localization here takes no pose (localization.source)");
    commands.set_pose = nav::Pose2{value[0], value[1], value[2]};
    commands.set_pose_action = id;
    if (const std::string last = Param(action, "lastNodeId"); !last.empty()) {
      last_node_id_ = last;
      last_node_position_ = nullptr;
    }
    SetStatus(action, kRunning);  // until the robot core answers
  } else {                        // startCharging, stopCharging
    if (!nodes_.empty() || !mission_id_.empty()) return fail("actionError", "an order is under way");
    if (type == "startCharging") {
      if (robot.docked) return SetStatus(action, kFinished);
      std::optional<nav::MissionGoal> dock = robot.pose && find_dock_ ? find_dock_(*robot.pose) : std::nullopt;
      if (!dock) return fail("actionError", "there is no dock on map " + robot.map_id);
      commands.start = std::vector<nav::MissionGoal>{*dock};
    } else {
      if (!robot.docked) return SetStatus(action, kFinished);
      commands.start = std::vector<nav::MissionGoal>{nav::UndockGoal(robot.pose, options_.dock)};
    }
    instant_mission_action_ = id;
    SetStatus(action, kRunning);
  }
}

VdaCommands VdaAgent::PoseAnswered(const std::string& action_id, const std::string& refusal) {
  VdaCommands commands;
  Action* action = FindAction(action_id);
  if (action == nullptr || !Open(action->status)) return commands;
  commands.send_state = true;
  changed_ = true;
  if (refusal.empty()) {
    SetStatus(*action, kFinished);
  } else {
    SetStatus(*action, kFailed, refusal);
    Reject("actionError", "initPosition: " + refusal, {{"actionId", action_id}, {"actionType", "initPosition"}});
  }
  return commands;
}

VdaCommands VdaAgent::InstantActions(const json& message, const VdaRobotNow& robot) {
  VdaCommands commands;
  for (const json& action : message["actions"]) RunInstant(action, robot, commands);
  return commands;
}

FleetOrder VdaAgent::Describe() const {
  FleetOrder view;
  view.order_id = order_id_;
  view.order_update_id = order_update_id_;
  view.last_node_id = last_node_id_;
  if (last_node_position_.is_object() && !order_id_.empty()) {
    view.nodes.push_back(
        {last_node_id_, true, Number(last_node_position_, "x", 0.0), Number(last_node_position_, "y", 0.0), true});
  }
  for (const Node& n : nodes_) {
    view.nodes.push_back({n.id, n.released, Number(n.position, "x", 0.0), Number(n.position, "y", 0.0), false});
  }
  for (const Edge& e : edges_) view.edges.push_back({e.id, e.start, e.end, e.released});
  return view;
}

void VdaAgent::FillState(json& state) {
  state["orderId"] = order_id_;
  state["orderUpdateId"] = order_update_id_;
  state["lastNodeId"] = last_node_id_;
  state["lastNodeSequenceId"] = last_node_sequence_;
  json nodes = json::array();
  for (const Node& n : nodes_) {
    json node = {{"nodeId", n.id}, {"sequenceId", n.sequence}, {"released", n.released}};
    if (n.position.is_object()) {
      node["nodePosition"] = {{"x", n.position["x"]}, {"y", n.position["y"]}, {"mapId", n.position["mapId"]}};
      if (n.position.contains("theta")) node["nodePosition"]["theta"] = n.position["theta"];
    }
    nodes.push_back(std::move(node));
  }
  state["nodeStates"] = std::move(nodes);
  json edges = json::array();
  for (const Edge& e : edges_)
    edges.push_back({{"edgeId", e.id}, {"sequenceId", e.sequence}, {"released", e.released}});
  state["edgeStates"] = std::move(edges);
  json actions = json::array();
  for (const Action& a : actions_) {
    json action = {{"actionId", a.id}, {"actionType", a.type}, {"actionStatus", a.status}};
    if (!a.result.empty()) action["resultDescription"] = a.result;
    actions.push_back(std::move(action));
  }
  state["actionStates"] = std::move(actions);
  json& errors = state["errors"];
  if (!errors.is_array()) errors = json::array();
  for (const Error& e : errors_) {
    json refs = json::array();
    for (const auto& [key, value] : e.references) refs.push_back({{"referenceKey", key}, {"referenceValue", value}});
    errors.push_back({{"errorType", e.type},
                      {"errorLevel", e.level},
                      {"errorDescription", e.description},
                      {"errorReferences", refs}});
  }
  changed_ = false;
}

}  // namespace corridor::server
