// The Open-RMF robot contract: what a fleet adapter built on Open-RMF's fleet_adapter_template asks of a robot
// (navigate, stop, dock, start_activity, localize, position, battery_soc, map, is_command_completed), kept apart from
// the HTTP routes that carry it (server/api/api_rmf.cc). The adapter numbers its commands; the robot says, by that
// number, whether one is done. Its state is reported as Open-RMF's robot_state (rmf_api_msgs).
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace corridor::server {

// Which mission carries each of the adapter's commands, or that a command was done when it was taken (localize,
// stop). The newest kKeep commands are remembered. Thread-safe.
class RmfCommands {
 public:
  static constexpr std::size_t kKeep = 100;

  void Carried(std::uint64_t cmd_id, std::string mission_id);
  void Done(std::uint64_t cmd_id);

  struct Command {
    std::uint64_t cmd_id = 0;
    std::string mission_id;  // empty: done when taken
  };
  std::optional<Command> Find(std::uint64_t cmd_id) const;

 private:
  void Remember(Command command);
  mutable std::mutex mutex_;
  std::deque<Command> commands_;
};

// What Open-RMF's robot_state needs of the robot, sampled from the bus.
struct RmfSample {
  std::string name;
  std::string map;
  bool has_pose = false;
  double x = 0.0, y = 0.0, yaw = 0.0;
  std::optional<double> battery;  // 0..1
  bool charging = false;
  std::string mission_id;      // the current or last mission
  std::string mission_status;  // nav::ToString(MissionStatus), empty without a mission
  std::string mission_error;
  bool stopped = false;  // the control loop stopped the robot (a fault, a device not answering)
  std::string stop_reason;
  bool lost = false;  // localization does not know where the robot is
  std::int64_t unix_millis = 0;
};

// Open-RMF's status token: uninitialized (no pose yet), error (stopped or lost), working (a mission under way),
// charging, or idle.
std::string RmfStatus(const RmfSample& sample);
// The robot_state document (rmf_api_msgs/schemas/robot_state.json): name, status, task_id (the active mission's
// id, else ""), unix_millis_time, location, battery, issues.
nlohmann::json RmfRobotState(const RmfSample& sample);

}  // namespace corridor::server
