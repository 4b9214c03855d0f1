// The robot's state at one instant: the latest message of each topic it is made of, taken together, and what the
// graph knows beside them (docked, the map in use, its floor, every node's health). The core makes one at most once a
// tick (RobotCore::State) and every reader shares it: REST's /state, the stream and DDS's corridor/state send its
// JSON text, made once with it; VDA 5050's and Open-RMF's states are projections of its fields.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "server/config/config.h"
#include "server/nodes/mission_node.h"
#include "server/runtime/messages.h"
#include "server/runtime/process_usage.h"

namespace corridor::server {

struct RobotState {
  drivers::TimeNs stamp_ns = 0;  // when it was taken (the graph's clock)
  double uptime_s = 0.0;         // since the graph started
  // The topics' latest messages; null: none yet.
  std::shared_ptr<const StampedPose> pose;
  std::shared_ptr<const drivers::WheelOdometry> odometry;
  std::shared_ptr<const BaseCommand> command;
  std::shared_ptr<const LocalizationState> localization;
  std::shared_ptr<const MissionState> mission;
  std::shared_ptr<const drivers::BatteryState> battery;
  std::shared_ptr<const DevicesHealth> devices;
  std::shared_ptr<const FleetOrder> fleet;
  std::shared_ptr<const FaceState> face;
  std::shared_ptr<const TrackedObjects> tracked;
  std::shared_ptr<const ControlLatency> latency;
  std::shared_ptr<const StampedPose> sim_true_pose;
  std::shared_ptr<const SimPedestrians> sim_pedestrians;
  std::optional<ProcessUsageSample> process;  // the daemon's CPU and memory, after its first second
  bool docked = false;
  std::string map;  // the map in use
  std::uint64_t map_revision = 0;
  bool map_traffic = false;          // the planner has traffic costs for it
  std::optional<std::string> floor;  // the building's floor of that map
  nlohmann::json nodes;              // each node's status, as Node::Status says it
  std::string text;                  // all of the above as JSON (ToJson), made once with it
};

// The JSON of GET /api/v1/state (openapi.json's RobotState), with the simulator's fixed obstacles from `config`.
nlohmann::json ToJson(const RobotState& state, const Config& config);

}  // namespace corridor::server
