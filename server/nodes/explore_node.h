// Exploration (RobotCore::Explore, on topics::kExploreCommand): while exploring, the planner plans on the map being
// built (rendered every few seconds on the mapping topic, handed on as topics::kExploringMap), and the robot is sent
// to the next frontier (nav/planner/frontiers.h) each time its last goal is over, reached or not (a goal is not
// offered twice), until no reachable frontier is left; then mapping stops, which saves the map (and makes it the map
// in use). A mission someone else starts, cancelling the exploration's own, or stopping mapping ends exploring, and
// the planner goes back to the map in use. Mapping without exploring leaves the planner on the map in use: goals given
// meanwhile are on the map the user sees. Whether it explores is on topics::kExploreState.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "nav/planner/frontiers.h"
#include "server/app/robot_core.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class ExploreNode final : public Node {
 public:
  ExploreNode(Executor& mapping, Bus& bus, const RobotCore& core, const nav::FrontierOptions& options = {});
  void Activate() override;

 private:
  // Explores the map being built (mapping is under way, or was started by whoever asked).
  void Explore(const ExploreCommand& command);
  void OnMapping(const MappingState& mapping);
  void OnMission(const MissionState& mission);
  // The planner on `mapping`'s map, and the next goal unless one is under way.
  void Plan(const MappingState& mapping);
  // The next frontier goal on the latest map (a mission asked of the core), or the end of exploring.
  void Next();
  // The core's answer to the last goal: its mission, or a refusal (that frontier is given up).
  void Started(const MissionResult& result);
  // Stops exploring; `save`: stop mapping (which saves the map); `cancel_goal`: the robot stops where it is.
  void Finish(const std::string& why, bool save, bool cancel_goal);

  void SetExploring(bool exploring);

  const RobotCore& core_;
  nav::FrontierOptions options_;
  bool exploring_ = false;
  std::shared_ptr<const MappingState> mapping_;  // the latest with a map, while mapping
  std::string mission_id_;                       // the current goal's mission; empty: none
  bool starting_ = false;                        // a goal asked of the core, not answered yet
  Eigen::Vector2d goal_ = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> given_up_;  // goals reached or failed

  // The topics it writes, resolved once.
  Topic<ExploringMap>& exploring_map_topic_ = bus().Get(topics::kExploringMap);
  Topic<ExploreState>& state_topic_ = bus().Get(topics::kExploreState);
};

}  // namespace corridor::server
