#include "server/runtime/messages.h"

#include <cmath>

namespace corridor::server {

nlohmann::json ToJson(const nav::Pose2& pose) { return {{"x", pose.x_m}, {"y", pose.y_m}, {"yaw", pose.yaw_rad}}; }

nlohmann::json ToJson(const LocalizationState& localization) {
  const nav::LocalizationEstimate& e = localization.estimate;
  nlohmann::json particles = nlohmann::json::array();
  for (const nav::Pose2& p : localization.particles) particles.push_back({p.x_m, p.y_m, p.yaw_rad});
  nlohmann::json covariance = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) covariance.push_back(e.covariance(r, c));
  }
  return {{"stamp_ns", localization.stamp_ns},
          {"source", localization.source},
          {"sensor", localization.sensor},
          {"look_around_rps", localization.look_around_rps},
          {"pose", ToJson(e.pose)},
          {"covariance", covariance},
          {"health", nav::ToString(e.health)},
          {"agreement", e.agreement},
          {"particle_count", e.particles},
          {"particles", particles}};
}

nlohmann::json ToJson(const ControlLatency& l) {
  return {
      {"rate_hz", l.rate_hz}, {"p50_ms", l.p50_ms}, {"p99_ms", l.p99_ms}, {"max_ms", l.max_ms}, {"samples", l.samples}};
}

nlohmann::json ToJson(const SimPedestrians& p) {
  nlohmann::json people = nlohmann::json::array();
  for (const auto& person : p.people) {
    people.push_back({{"x", person.position.x()},
                      {"y", person.position.y()},
                      {"vx", person.velocity.x()},
                      {"vy", person.velocity.y()},
                      {"radius_m", p.radius_m}});
  }
  return people;
}

nlohmann::json ToJson(const TrackedObjects& t) {
  nlohmann::json objects = nlohmann::json::array();
  for (const nav::TrackedObject& o : t.surroundings.objects) {
    nlohmann::json object = {{"x", o.position.x()},  {"y", o.position.y()},    {"vx", o.velocity.x()},
                             {"vy", o.velocity.y()}, {"radius_m", o.radius_m}, {"moving", o.moving},
                             {"seen", o.seen}};
    if (o.turn_at) object["walk_end"] = {{"x", o.turn_at->x()}, {"y", o.turn_at->y()}};
    objects.push_back(std::move(object));
  }
  return objects;
}

nlohmann::json ToJson(const face::Detection& d) {
  using nlohmann::json;
  return {{"class", d.label},
          {"score", d.score},
          {"box",
           d.box ? json{{"x", d.box->x}, {"y", d.box->y}, {"w", d.box->width}, {"h", d.box->height}} : json(nullptr)},
          {"position",
           d.position ? json{{"x", d.position->x()}, {"y", d.position->y()}, {"z", d.position->z()}} : json(nullptr)},
          {"bearing", d.bearing_rad ? json(*d.bearing_rad) : json(nullptr)},
          {"track_id", d.track_id},
          {"source", d.source}};
}

nlohmann::json ToJson(const Detections& detections) {
  nlohmann::json items = nlohmann::json::array();
  for (const face::Detection& d : detections.items) items.push_back(ToJson(d));
  return {{"stamp", drivers::ToSeconds(detections.stamp_ns)}, {"detections", std::move(items)}};
}

nlohmann::json ToJson(const FaceState& face) {
  return {{"expression", std::string(face::ToString(face.expression))},
          {"gaze", face.gaze_rad},
          {"gaze_at_person", face.gaze_at_person},
          {"said_sequence", face.said_sequence},
          {"said", face.said},
          {"said_kind", face.said_kind}};
}

nlohmann::json ToJson(const GroundLanes& g) {
  nlohmann::json lanes = nlohmann::json::array();
  for (const nav::LaneResult& l : g.lanes) {
    nlohmann::json lane = {
        {"offset_m", l.offset_m}, {"free_distance_m", l.free_distance_m}, {"dead_end", l.dead_end}, {"blind", l.blind}};
    if (l.dead_end && !l.blind) {
      lane["pixel"] = {l.pixel.x(), l.pixel.y()};
      lane["point"] = {l.point.x(), l.point.y(), l.point.z()};
    }
    lanes.push_back(std::move(lane));
  }
  return {{"frame_sequence", g.frame_sequence}, {"latency_ms", g.latency_ms}, {"lanes", std::move(lanes)}};
}

nlohmann::json ToJson(const MissionState& m) {
  nlohmann::json goals = nlohmann::json::array();
  for (const nav::MissionGoal& g : m.goals) {
    nlohmann::json goal = {{"x", g.pose.x_m}, {"y", g.pose.y_m}};
    if (g.has_yaw) goal["yaw"] = g.pose.yaw_rad;
    if (!g.place.empty()) goal["place"] = g.place;
    goal["action"] = nav::ToString(g.action);
    if (!g.floor.empty()) goal["floor"] = g.floor;
    if (g.action == nav::GoalAction::kRideLift) {
      goal["lift"] = g.lift;
      goal["ride_to"] = g.ride_to;
    }
    goals.push_back(std::move(goal));
  }
  nlohmann::json path = nlohmann::json::array();
  for (const nav::Pose2& p : m.path) path.push_back(ToJson(p));
  return {{"id", m.id},
          {"status", nav::ToString(m.status)},
          {"waypoints", std::move(goals)},
          {"current_waypoint", m.current},
          {"progress", m.progress},
          {"eta_s", m.eta_s},
          {"remaining_on_leg_m", m.remaining_on_leg_m},
          {"path", std::move(path)},
          {"policy", nav::ToString(m.policy)},
          {"error", m.error},
          {"docking", m.docking},
          {"waiting_for_door", m.waiting_for_door},
          {"waiting", m.waiting},
          {"lift", m.lift},
          {"speed_limit_mps", std::isfinite(m.speed_limit_mps) ? nlohmann::json(m.speed_limit_mps) : nullptr}};
}

nlohmann::json ToJson(const drivers::BatteryState& b) {
  return {{"percent", b.charge * 100.0},
          {"voltage_v", b.voltage_v},
          {"current_a", b.current_a},
          {"charging", b.charging},
          {"on_charger", b.on_charger}};
}

nlohmann::json ToJson(const FleetOrder& o) {
  nlohmann::json nodes = nlohmann::json::array();
  for (const FleetOrder::Node& n : o.nodes) {
    nodes.push_back({{"id", n.id}, {"released", n.released}, {"x", n.x}, {"y", n.y}, {"traversed", n.traversed}});
  }
  nlohmann::json edges = nlohmann::json::array();
  for (const FleetOrder::Edge& e : o.edges) {
    edges.push_back({{"id", e.id}, {"start", e.start}, {"end", e.end}, {"released", e.released}});
  }
  return {{"protocol", o.protocol},         {"connected", o.connected},
          {"order_id", o.order_id},         {"order_update_id", o.order_update_id},
          {"last_node_id", o.last_node_id}, {"nodes", std::move(nodes)},
          {"edges", std::move(edges)}};
}

nlohmann::json ToJson(const LocalStepState& s) {
  nlohmann::json remembered = nlohmann::json::array();
  for (const Eigen::Vector2d& p : s.remembered) remembered.push_back({p.x(), p.y()});
  return {{"stamp_s", drivers::ToSeconds(s.stamp_ns)},
          {"twist", ToJson(s.step.twist)},
          {"mode", nav::ToString(s.step.mode)},
          {"avoiding", s.step.avoiding},
          {"guarded", s.step.guarded},
          {"evading", s.step.evading},
          {"nearest_m", std::isfinite(s.step.nearest_m) ? nlohmann::json(s.step.nearest_m) : nullptr},
          {"remaining_m", s.step.remaining_m},
          {"remembered", std::move(remembered)}};
}

nlohmann::json ToJson(const nav::Twist2& twist) {
  return {{"linear_mps", twist.linear_mps}, {"angular_rps", twist.angular_rps}};
}

nlohmann::json ToJson(const StampedPose& pose) {
  nlohmann::json j = ToJson(pose.pose);
  j["stamp_s"] = drivers::ToSeconds(pose.stamp_ns);
  return j;
}

nlohmann::json ToJson(const drivers::WheelOdometry& odometry) {
  return {{"stamp_s", drivers::ToSeconds(odometry.stamp_ns)},
          {"pose", ToJson(odometry.odom_T_base)},
          {"velocity", ToJson(odometry.velocity)},
          {"bumper_pressed", odometry.bumper_pressed}};
}

nlohmann::json ToJson(const drivers::LaserScan& scan) {
  nlohmann::json ranges = nlohmann::json::array();
  for (float r : scan.ranges) {
    if (std::isfinite(r)) {
      ranges.push_back(r);
    } else {
      ranges.push_back(nullptr);  // JSON has no infinity: null means no return
    }
  }
  return {{"stamp_s", drivers::ToSeconds(scan.stamp_ns)},
          {"angle_min_rad", scan.angle_min_rad},
          {"angle_increment_rad", scan.angle_increment_rad},
          {"range_max_m", scan.range_max_m},
          {"ranges", std::move(ranges)}};
}

nlohmann::json ToJson(const TeleopCommand& command) {
  nlohmann::json j = ToJson(command.twist);
  j["source"] = command.source;
  return j;
}

nlohmann::json ToJson(const BaseCommand& command) {
  nlohmann::json j = ToJson(command.twist);
  j["mode"] = nav::ToString(command.mode);
  j["reason"] = StopReason(command);
  return j;
}

std::string StopReason(const BaseCommand& command) {
  if (command.reason == nav::GateReason::kProtectiveStop && !command.detail.empty()) {
    return std::string("protective stop: ") + command.detail;
  }
  if (command.reason == nav::GateReason::kDeviceDown && !command.detail.empty()) return command.detail;
  return nav::ToString(command.reason);
}

nlohmann::json ToJson(const DevicesHealth& health) {
  nlohmann::json devices = nlohmann::json::array();
  for (const DeviceReport& d : health.devices) {
    devices.push_back({{"device", d.device},
                       {"driver", d.driver},
                       {"port", d.port},
                       {"state", nav::ToString(d.state)},
                       {"rate_hz", d.rate_hz},
                       {"age_s", d.age_s >= 0.0 ? nlohmann::json(d.age_s) : nlohmann::json(nullptr)},
                       {"link", d.link.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.link)},
                       {"reconnects", d.reconnects},
                       {"last_error", d.last_error.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.last_error)},
                       {"handoff_cpu_s", d.handoff_cpu_s}});
  }
  return {{"stamp_s", drivers::ToSeconds(health.stamp_ns)}, {"devices", std::move(devices)}};
}

nlohmann::json ToJson(const Fault& fault) {
  return {{"stamp_s", drivers::ToSeconds(fault.stamp_ns)},
          {"node", fault.node},
          {"loop", fault.loop},
          {"what", fault.what}};
}

}  // namespace corridor::server
