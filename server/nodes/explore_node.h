// Exploration (POST /api/v1/mapping/explore): while exploring, the planner plans on the map being built (rendered every
// few seconds on the mapping topic), and the robot is sent to the next frontier (nav/planner/frontiers.h) each time
// its last goal is over, reached or not (a goal is not offered twice), until no reachable frontier is left; then
// mapping stops, which saves the map (and makes it the planner's). A mission someone else starts, cancelling the
// exploration's own, or stopping mapping ends exploring, and the planner gets the active map back. Mapping without
// exploring leaves the planner on the active map: goals given meanwhile are on the map the user sees.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "nav/planner/frontiers.h"
#include "server/app/robot_core.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class ExploreNode final : public Node {
 public:
  // `restore_map`: gives the planner the active map again.
  ExploreNode(Executor& mapping, Bus& bus, PlannerService& planner, const RobotCore& core,
              std::function<void()> restore_map, const nav::FrontierOptions& options = {});
  void Activate() override;
  // Explores the map being built (mapping must be under way, or be started by the caller). Thread-safe.
  void Explore();
  // Whether it is exploring now. Thread-safe.
  bool exploring() const { return exploring_; }

 private:
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

  PlannerService& planner_;
  const RobotCore& core_;
  std::function<void()> restore_map_;
  nav::FrontierOptions options_;
  std::atomic<bool> exploring_{false};
  std::shared_ptr<const MappingState> mapping_;  // the latest with a map, while mapping
  std::string mission_id_;                       // the current goal's mission; empty: none
  bool starting_ = false;                        // a goal asked of the core, not answered yet
  Eigen::Vector2d goal_ = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> given_up_;  // goals reached or failed
};

}  // namespace corridor::server
