#include "server/nodes/vda5050_node.h"

#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

using json = nlohmann::json;

std::int64_t UnixMillis() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

VdaIdentity IdentityOf(const Vda5050Options& o, const std::string& robot_name) {
  return {o.interface_name, o.manufacturer, o.serial_number.empty() ? robot_name : o.serial_number};
}

VdaMissionProgress ProgressOf(const MissionState& m) { return {m.id, m.status, m.current, m.goals.size(), m.error}; }

// What of the robot counts as a change the state must report at once (the standard's events).
std::string StateKey(const VdaRobot& r) {
  return json{r.driving,
              r.paused,
              r.manual,
              r.protective_stop,
              r.charging,
              r.errors.size(),
              r.battery_percent.has_value(),
              r.map_id,
              r.position_initialized}
      .dump();
}

// Each goal's node (the agent names a goal's place after its node).
std::vector<std::string> NodesOf(const std::vector<nav::MissionGoal>& goals) {
  std::vector<std::string> nodes;
  for (const nav::MissionGoal& g : goals) nodes.push_back(g.place);
  return nodes;
}

// The robot's name as a topic level: what the standard allows, the rest as '_'.
std::string TopicLevel(std::string name) {
  for (char& c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == ':' || c == '-';
    if (!ok) c = '_';
  }
  return name.empty() ? std::string("corridor") : name;
}

}  // namespace

Vda5050Node::Vda5050Node(Executor& io, Bus& bus, const Config& config, const RobotCore& core, std::string robot_name)
    : PeriodicNode("vda5050", io, bus, config.fleet.vda5050.visualization_hz),
      options_(config.fleet.vda5050),
      config_(config),
      identity_(IdentityOf(options_, TopicLevel(std::move(robot_name)))),
      core_(core),
      agent_({0.5, config.mission.docking.dock}, [&core](const nav::Pose2& near) { return core.NearestDock(near); }),
      sent_(Loop("send")) {
  vehicle_.max_speed_mps = config.mission.navigator.follower.max_linear_mps;
  vehicle_.max_deceleration_mps2 = config.safety.stopping.max_decel_mps2;
  vehicle_.radius_m = config.planner.robot_radius_m;
  MqttLinkOptions link;
  link.broker = options_.broker;
  link.client_id = identity_.manufacturer + "-" + identity_.serial_number;
  link.subscriptions = {VdaTopic(identity_, "order"), VdaTopic(identity_, "instantActions")};
  link.subscription_qos = options_.qos;
  link.will = {VdaTopic(identity_, "connection"),
               VdaConnection(identity_, NextHeader(VdaMessage::kConnection), "CONNECTIONBROKEN").dump(), 1, true};
  link_ = std::make_unique<MqttLink>(
      std::move(link),
      [this](std::string topic, std::string payload) {
        executor().Post([this, topic = std::move(topic), payload = std::move(payload)] {
          Run("message", [&] { Received(topic, payload); });
        });
      },
      [this] { executor().Post([this] { Run("connected", [&] { Connected(); }); }); });
}

void Vda5050Node::Activate() {
  Subscribe(topics::kMission, "mission", [this](const std::shared_ptr<const MissionState>& m) { OnMission(*m); });
  PeriodicNode::Activate();
  PublishOrder();
  link_->Connect();
  SetHealth(Health::kDegraded, "connecting to " + options_.broker);
}

void Vda5050Node::Deactivate() {
  PeriodicNode::Deactivate();
  link_->Stop({VdaTopic(identity_, "connection"),
               VdaConnection(identity_, NextHeader(VdaMessage::kConnection), "OFFLINE").dump(), 1, true});
}

VdaHeader Vda5050Node::NextHeader(VdaMessage kind) { return {header_ids_[kind]++, VdaTimestamp(UnixMillis())}; }

void Vda5050Node::Send(VdaMessage kind, json message, bool retained) {
  const std::vector<std::string> problems = schemas_.Check(kind, message);
  if (!problems.empty()) {
    spdlog::error("vda5050: not sending an invalid {}: {}", ToString(kind), problems.front());
    return;
  }
  const int qos = kind == VdaMessage::kConnection ? 1 : options_.qos;
  const auto start = std::chrono::steady_clock::now();
  if (link_->Publish({VdaTopic(identity_, ToString(kind)), message.dump(), qos, retained})) {
    sent_.Record(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
}

void Vda5050Node::Connected() {
  SetHealth(Health::kOk, "connected to " + options_.broker);
  Send(VdaMessage::kConnection, VdaConnection(identity_, NextHeader(VdaMessage::kConnection), "ONLINE"), true);
  SendState();
}

VdaRobotNow Vda5050Node::Now() {
  const std::shared_ptr<const RobotState> state = core_.State();
  VdaRobotNow now;
  if (state->pose) now.pose = state->pose->pose;
  now.map_id = state->map;
  now.docked = state->docked;
  now.can_set_pose = config_.localization.source == LocalizationOptions::Source::kMonteCarlo;
  return now;
}

VdaRobot Vda5050Node::Sample() {
  const std::shared_ptr<const RobotState> state = core_.State();
  const RobotState& s = *state;
  VdaRobot r;
  r.map_id = s.map;
  if (const auto& pose = s.pose) {
    r.position_initialized = true;
    r.pose = pose->pose;
    r.localization_score = 1.0;
  }
  if (const auto& localization = s.localization; localization && localization->source == "mcl") {
    r.localization_score = std::clamp(localization->estimate.agreement, 0.0, 1.0);
    if (localization->estimate.health == nav::LocalizationHealth::kLost) {
      r.errors.push_back({"localizationError", "WARNING", "localization does not know where the robot is"});
    }
  }
  if (const auto& odometry = s.odometry) {
    r.velocity = odometry->velocity;
    r.driving = std::abs(odometry->velocity.linear_mps) > 0.01 || std::abs(odometry->velocity.angular_rps) > 0.02;
  }
  if (const auto& battery = s.battery) {
    r.battery_percent = 100.0 * battery->charge;
    r.battery_voltage_v = battery->voltage_v;
    r.charging = battery->charging;
  }
  if (const auto& mission = s.mission) {
    r.paused = mission->status == nav::MissionStatus::kPaused;
  }
  r.paused = r.paused || agent_.paused();
  if (const auto& command = s.command) {
    r.manual = command->mode == nav::ControlMode::kTeleop;
    if (command->mode == nav::ControlMode::kStopped) {
      r.protective_stop = true;
      r.errors.push_back(
          {"protectiveStop", "WARNING", std::string("the robot is held still: ") + nav::ToString(command->reason)});
    }
    r.field_violation = command->reason != nav::GateReason::kNone && command->mode != nav::ControlMode::kStopped;
  }
  return r;
}

void Vda5050Node::PublishOrder() {
  FleetOrder order = agent_.Describe();
  order.stamp_ns = clock().Now();
  order.protocol = "vda5050";
  order.connected = link_->connected();
  bus().Get(topics::kFleetOrder).Publish(std::move(order));
}

void Vda5050Node::SendState() { SendState(Sample()); }

void Vda5050Node::SendState(const VdaRobot& robot) {
  if (agent_.changed()) PublishOrder();
  json state = VdaState(identity_, NextHeader(VdaMessage::kState), robot);
  agent_.FillState(state);
  last_state_s_ = drivers::ToSeconds(clock().Now());
  last_state_key_ = StateKey(robot);
  Send(VdaMessage::kState, std::move(state));
}

void Vda5050Node::Tick() {
  link_->Connect();
  if (link_->connected() != shown_connected_) {
    shown_connected_ = link_->connected();
    PublishOrder();
  }
  if (!link_->connected()) return;
  const VdaRobot robot = Sample();
  Send(VdaMessage::kVisualization, VdaVisualization(identity_, NextHeader(VdaMessage::kVisualization), robot));
  const double now_s = drivers::ToSeconds(clock().Now());
  if (agent_.changed() || StateKey(robot) != last_state_key_ || now_s - last_state_s_ >= options_.state_interval_s) {
    SendState(robot);
  }
}

void Vda5050Node::Received(const std::string& topic, const std::string& payload) {
  const bool order = topic == VdaTopic(identity_, "order");
  const VdaMessage kind = order ? VdaMessage::kOrder : VdaMessage::kInstantActions;
  json message;
  try {
    message = json::parse(payload);
  } catch (const json::parse_error& e) {
    agent_.Invalid(ToString(kind), {std::string("not JSON: ") + e.what()});
    SendState();
    return;
  }
  if (const auto problems = schemas_.Check(kind, message); !problems.empty()) {
    spdlog::warn("vda5050: an invalid {} refused: {}", ToString(kind), problems.front());
    agent_.Invalid(ToString(kind), problems);
    SendState();
    return;
  }
  Carry(order ? agent_.Order(message, Now()) : agent_.InstantActions(message, Now()));
}

void Vda5050Node::OnMission(const MissionState& mission) { Carry(agent_.Progress(ProgressOf(mission))); }

void Vda5050Node::StartMission(std::vector<nav::MissionGoal> goals) {
  std::vector<std::string> nodes = NodesOf(goals);
  const std::size_t asked = goals.size();
  Executor& io = executor();  // outlives the node; work posted after the graph stops is not run
  core_.StartMission({std::move(goals), std::numeric_limits<double>::infinity(), "vda5050"},
                     [this, &io, nodes = std::move(nodes), asked](MissionResult result) {
                       io.Post([this, nodes, asked, result = std::move(result)] {
                         Run("started", [&] { Answered(result, nodes, asked); });
                       });
                     });
}

void Vda5050Node::SetPose(const nav::Pose2& pose, const std::string& action_id) {
  PoseOrder order;
  order.pose = pose;
  order.origin = "vda5050";
  Executor& io = executor();
  core_.SetPose(order, [this, &io, action_id](PoseResult result) {
    const auto* refused = std::get_if<PoseRefused>(&result);
    io.Post([this, action_id, refusal = refused ? refused->detail : std::string()] {
      Run("pose answered", [&] { Carry(agent_.PoseAnswered(action_id, refusal)); });
    });
  });
}

void Vda5050Node::ExtendMission(std::vector<nav::MissionGoal> goals) {
  const std::string id = agent_.mission_id();
  Executor& io = executor();
  core_.ExtendMission(id, goals, "vda5050", [this, &io, id, goals](ExtendResult result) {
    io.Post([this, id, goals, result = std::move(result)] {
      Run("extended", [&] {
        if (const auto* refusal = std::get_if<nav::MissionRefusal>(&result)) return Refused(*refusal, NodesOf(goals));
        if (std::get<nav::TransitionOutcome>(result) == nav::TransitionOutcome::kOk) return agent_.Extended();
        // The mission ended meanwhile: its last progress first, then a new one for these goals.
        if (const auto last = core_.Mission(id)) Carry(agent_.Progress(ProgressOf(*last)));
        StartMission(goals);
      });
    });
  });
}

void Vda5050Node::Refused(const nav::MissionRefusal& refusal, const std::vector<std::string>& nodes) {
  // Off the map or on an unknown floor: the order names what is not there; otherwise there is no way to it.
  const bool invalid =
      refusal.reason == nav::GoalRefusal::kOutsideMap || refusal.reason == nav::GoalRefusal::kUnknownFloor;
  const std::string node = refusal.goal && *refusal.goal < nodes.size() ? nodes[*refusal.goal] : "";
  const std::string description = nav::Describe(refusal, "node " + node);
  spdlog::warn("vda5050: an order refused: {}", description);
  Carry(agent_.Refused(invalid ? "validationError" : "noRouteError", description, node));
}

void Vda5050Node::Answered(const MissionResult& result, const std::vector<std::string>& nodes, std::size_t asked) {
  if (const auto* refusal = std::get_if<nav::MissionRefusal>(&result)) return Refused(*refusal, nodes);
  const MissionState& state = std::get<MissionState>(result);
  Carry(agent_.Started(state.id, state.goals.size() - asked));
  if (agent_.paused()) core_.Command(MissionStep::kPause, state.id, "vda5050");
  // What the mission did while the answer was on its way (it may have ended already).
  if (const auto now = core_.Mission(state.id)) Carry(agent_.Progress(ProgressOf(*now)));
}

void Vda5050Node::Carry(VdaCommands c) {
  if (!c.cancel.empty()) core_.Command(MissionStep::kCancel, c.cancel, "vda5050");
  if (c.start) StartMission(std::move(*c.start));
  if (!c.extend.empty()) ExtendMission(std::move(c.extend));
  if (c.pause && !agent_.mission_id().empty()) core_.Command(MissionStep::kPause, agent_.mission_id(), "vda5050");
  if (c.resume && !agent_.mission_id().empty()) {
    core_.Command(MissionStep::kResume, agent_.mission_id(), "vda5050");
  }
  if (c.set_pose) SetPose(*c.set_pose, c.set_pose_action);
  for (std::string& text : c.say) {
    FaceCommand command;
    command.say = std::move(text);
    bus().Get(topics::kFaceCommand).Publish(command);
  }
  if (c.send_factsheet) {
    json factsheet = VdaFactsheet(identity_, NextHeader(VdaMessage::kFactsheet), vehicle_);
    factsheet["protocolFeatures"]["agvActions"] = VdaAgent::FactsheetActions();
    Send(VdaMessage::kFactsheet, std::move(factsheet));
  }
  if (c.send_state || agent_.changed()) SendState();
}

}  // namespace corridor::server
