#include "server/nodes/explore_node.h"

#include <limits>

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {

ExploreNode::ExploreNode(Executor& mapping, Bus& bus, const RobotCore& core, const nav::FrontierOptions& options)
    : Node("explore", mapping, bus), core_(core), options_(options) {}

void ExploreNode::Activate() {
  Subscribe(topics::kMapping, "mapping", [this](const auto& mapping) { OnMapping(*mapping); });
  Subscribe(topics::kMission, "mission", [this](const auto& mission) { OnMission(*mission); });
  Subscribe(topics::kExploreCommand, "explore", [this](const auto& command) { Explore(*command); });
  SetExploring(false);
}

void ExploreNode::SetExploring(bool exploring) {
  exploring_ = exploring;
  SetHealth(Health::kOk, exploring ? "exploring" : "not exploring");
  state_topic_.Publish(ExploreState{exploring});
}

void ExploreNode::Explore(const ExploreCommand& command) {
  SetExploring(true);
  given_up_.clear();
  mission_id_.clear();
  spdlog::info("explore: looking for frontiers, from {}", command.origin);
  if (mapping_) Plan(*mapping_);  // else on the first map rendered
}

void ExploreNode::OnMapping(const MappingState& mapping) {
  if (!mapping.active) {
    if (exploring_) Finish("mapping stopped", false, true);
    mapping_.reset();
    return;
  }
  if (!mapping.grid || (mapping_ && mapping.revision == mapping_->revision)) return;
  mapping_ = std::make_shared<const MappingState>(mapping);
  if (exploring_) Plan(*mapping_);
}

void ExploreNode::Plan(const MappingState& mapping) {
  exploring_map_topic_.Publish(ExploringMap{mapping.grid});
  if (mission_id_.empty() && !starting_) Next();
}

void ExploreNode::OnMission(const MissionState& mission) {
  if (!exploring_ || starting_) return;  // while starting, Started looks at the latest mission
  if (mission.id != mission_id_) {
    // Someone else sent the robot somewhere: they drive now.
    if (mission.status == nav::MissionStatus::kActive) Finish("another mission started", false, false);
    return;
  }
  switch (mission.status) {
    case nav::MissionStatus::kActive:
    case nav::MissionStatus::kPaused: return;
    case nav::MissionStatus::kCanceled: Finish("its goal was cancelled", false, false); return;
    case nav::MissionStatus::kSucceeded:
    case nav::MissionStatus::kFailed:
      given_up_.push_back(goal_);
      mission_id_.clear();
      Next();
      return;
  }
}

void ExploreNode::Next() {
  const auto pose = bus().Get(topics::kPose).latest();
  if (!mapping_ || !mapping_->grid || !pose) return;  // on the next map
  const std::optional<nav::FrontierGoal> goal =
      nav::NextFrontierGoal(*mapping_->grid, pose->pose.translation(), given_up_, options_);
  if (!goal) {
    Finish("no reachable frontier is left", true, false);
    return;
  }
  goal_ = goal->position;
  nav::MissionGoal target;
  target.pose = {goal_.x(), goal_.y(), 0.0};
  spdlog::info("explore: to ({:.2f}, {:.2f}), {:.1f} m away; {} frontier(s) reachable", goal_.x(), goal_.y(),
               goal->path_m, goal->frontiers);
  starting_ = true;
  Executor& mapping = executor();  // outlives the node; work posted after the graph stops is not run
  core_.StartMission({{target}, std::numeric_limits<double>::infinity(), "explore"},
                     [this, &mapping](MissionResult result) {
                       mapping.Post([this, result = std::move(result)] { Run("started", [&] { Started(result); }); });
                     });
}

void ExploreNode::Started(const MissionResult& result) {
  starting_ = false;
  const auto* state = std::get_if<MissionState>(&result);
  if (!exploring_) {  // ended meanwhile: nobody wants the robot at that frontier now
    if (state != nullptr) core_.Command(MissionStep::kCancel, state->id, "explore");
    return;
  }
  if (state == nullptr) {
    const auto& refusal = std::get<nav::MissionRefusal>(result);
    spdlog::info("explore: ({:.2f}, {:.2f}) refused: {}", goal_.x(), goal_.y(), nav::Describe(refusal, "the frontier"));
    given_up_.push_back(goal_);
    Next();
    return;
  }
  mission_id_ = state->id;
  // The mission topic while the answer was on its way: ours (perhaps over already), or one someone started since.
  if (const auto latest = bus().Get(topics::kMission).latest()) OnMission(*latest);
}

void ExploreNode::Finish(const std::string& why, bool save, bool cancel_goal) {
  SetExploring(false);
  if (cancel_goal && !mission_id_.empty()) core_.Command(MissionStep::kCancel, mission_id_, "explore");
  mission_id_.clear();
  spdlog::info("explore: done, {}{}", why, save ? ": saving the map" : "");
  exploring_map_topic_.Publish(ExploringMap{});  // saved, the new map is in use soon after
  if (save) {
    LocalizationCommand stop;
    stop.kind = LocalizationCommand::Kind::kStopMapping;
    bus().Get(topics::kLocalizationCommand).Publish(stop);
  }
}

}  // namespace corridor::server
