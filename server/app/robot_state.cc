#include "server/app/robot_state.h"

#include <algorithm>
#include <cmath>

#include "face/expression.h"

namespace corridor::server {

using nlohmann::json;

namespace {

template <typename T>
json OrNull(const std::shared_ptr<const T>& message) {
  return message ? ToJson(*message) : json(nullptr);
}

}  // namespace

json ToJson(const RobotState& s, const Config& config) {
  json state;
  state["stamp_s"] = s.uptime_s;
  state["pose"] = s.pose ? ToJson(s.pose->pose) : json(nullptr);
  state["velocity"] = ToJson(s.odometry ? s.odometry->velocity : nav::Twist2{});
  state["bumper_pressed"] = s.odometry && s.odometry->bumper_pressed;
  state["mode"] = s.command ? nav::ToString(s.command->mode) : "starting";
  state["stop_reason"] = s.command ? StopReason(*s.command) : "";
  state["command"] = ToJson(s.command ? s.command->twist : nav::Twist2{});
  state["sim_true_pose"] = s.sim_true_pose ? ToJson(s.sim_true_pose->pose) : json(nullptr);
  state["sim_pedestrians"] = s.sim_pedestrians ? ToJson(*s.sim_pedestrians) : json::array();
  state["tracked_objects"] = s.tracked ? ToJson(*s.tracked) : json::array();
  json obstacles = json::array();
  for (const drivers::sim::StaticObstacle& o : config.sim.obstacles) {
    obstacles.push_back({{"shape", drivers::sim::ShapeName(o.shape)},
                         {"x", o.center.x()},
                         {"y", o.center.y()},
                         {"size_m", o.size_m},
                         {"yaw", o.yaw_rad}});
  }
  state["sim_obstacles"] = std::move(obstacles);
  state["control_latency"] = OrNull(s.latency);
  state["face"] = std::string(face::ToString(s.face ? s.face->expression : face::Expression::kNeutral));
  state["mission"] = OrNull(s.mission);
  state["battery"] = OrNull(s.battery);
  state["devices"] = s.devices ? ToJson(*s.devices)["devices"] : json::array();
  state["docked"] = s.docked;
  state["fleet"] = OrNull(s.fleet);
  state["map"] = {{"name", s.map}, {"revision", s.map_revision}, {"traffic", s.map_traffic}};
  state["floor"] = s.floor ? json(*s.floor) : json(nullptr);
  state["nodes"] = s.nodes;
  // How sure localization is, for the console's plots: null unless the filter localizes.
  if (s.localization && s.localization->source == "mcl") {
    const nav::LocalizationEstimate& e = s.localization->estimate;
    state["localization"] = {{"health", nav::ToString(e.health)},
                             {"agreement", e.agreement},
                             {"sigma_m", std::sqrt(std::max(0.0, e.covariance(0, 0) + e.covariance(1, 1)))}};
  } else {
    state["localization"] = nullptr;
  }
  state["process"] = s.process ? json{{"cpu_percent", s.process->cpu_percent}, {"resident_mb", s.process->resident_mb}}
                               : json(nullptr);
  return state;
}

}  // namespace corridor::server
