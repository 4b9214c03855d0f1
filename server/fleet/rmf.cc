#include "server/fleet/rmf.h"

namespace corridor::server {

void RmfCommands::Remember(Command command) {
  std::lock_guard lock(mutex_);
  std::erase_if(commands_, [&](const Command& c) { return c.cmd_id == command.cmd_id; });
  commands_.push_back(std::move(command));
  while (commands_.size() > kKeep) commands_.pop_front();
}

void RmfCommands::Carried(std::uint64_t cmd_id, std::string mission_id) { Remember({cmd_id, std::move(mission_id)}); }

void RmfCommands::Done(std::uint64_t cmd_id) { Remember({cmd_id, ""}); }

std::optional<RmfCommands::Command> RmfCommands::Find(std::uint64_t cmd_id) const {
  std::lock_guard lock(mutex_);
  for (auto it = commands_.rbegin(); it != commands_.rend(); ++it) {
    if (it->cmd_id == cmd_id) return *it;
  }
  return std::nullopt;
}

namespace {

bool Underway(const RmfSample& s) { return s.mission_status == "active" || s.mission_status == "paused"; }

}  // namespace

std::string RmfStatus(const RmfSample& s) {
  if (!s.has_pose) return "uninitialized";
  if (s.stopped || s.lost) return "error";
  if (Underway(s)) return "working";
  if (s.charging) return "charging";
  return "idle";
}

nlohmann::json RmfRobotState(const RmfSample& s) {
  nlohmann::json issues = nlohmann::json::array();
  if (s.stopped) issues.push_back({{"category", "stopped"}, {"detail", s.stop_reason}});
  if (s.lost) issues.push_back({{"category", "lost"}, {"detail", "localization does not know where the robot is"}});
  if (s.mission_status == "failed") {
    issues.push_back(
        {{"category", "mission_failed"}, {"detail", {{"mission", s.mission_id}, {"error", s.mission_error}}}});
  }
  nlohmann::json state = {{"name", s.name},
                          {"status", RmfStatus(s)},
                          {"task_id", Underway(s) ? s.mission_id : ""},
                          {"unix_millis_time", s.unix_millis},
                          {"issues", std::move(issues)}};
  if (s.has_pose) state["location"] = {{"map", s.map}, {"x", s.x}, {"y", s.y}, {"yaw", s.yaw}};
  if (s.battery) state["battery"] = *s.battery;
  return state;
}

}  // namespace corridor::server
