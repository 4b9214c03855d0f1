#include "nav/safety/command_gate.h"

#include <algorithm>
#include <cmath>

namespace corridor::nav {

const char* ToString(ControlMode mode) {
  switch (mode) {
    case ControlMode::kIdle: return "idle";
    case ControlMode::kTeleop: return "teleop";
    case ControlMode::kMission: return "mission";
    case ControlMode::kDocking: return "docking";
    case ControlMode::kStopped: return "stopped";
  }
  return "unknown";
}

const char* ToString(GateReason reason) {
  switch (reason) {
    case GateReason::kNone: return "";
    case GateReason::kNoOdometry: return "no odometry from the base";
    case GateReason::kProtectiveStop: return "protective stop: a part of the daemon failed";
    case GateReason::kShuttingDown: return "shutting down";
    case GateReason::kBumpedForward: return "bumper pressed: not driving forward";
    case GateReason::kBumpedBacking: return "bumper pressed: not backing";
    case GateReason::kSlowedForObstacle: return "slowed for an obstacle ahead";
    case GateReason::kNoDepth: return "no depth frames: not driving forward";
    case GateReason::kSlowedForPerson: return "slowed near a person ahead";
    case GateReason::kNoLaser: return "no laser scans: not driving forward";
    case GateReason::kCliff: return "a cliff or a dropped wheel: stopped";
    case GateReason::kDeviceDown: return "a device is not answering";
  }
  return "unknown";
}

const char* ToString(Device device) {
  switch (device) {
    case Device::kBase: return "base";
    case Device::kLaser: return "laser";
    case Device::kCamera: return "camera";
  }
  return "unknown";
}

void CommandGate::Odometry(double now_s, bool bumper_pressed, bool cliff) {
  last_odometry_s_ = now_s;
  cliff_ = cliff;
  if (!bumper_pressed) return;
  last_bump_s_ = now_s;
  if (last_moving_linear_mps_ != 0.0) bump_direction_ = last_moving_linear_mps_ > 0.0 ? 1 : -1;
}

std::optional<Device> CommandGate::down() const {
  for (int d = 0; d < kDeviceCount; ++d) {
    if (down_[d]) return static_cast<Device>(d);
  }
  return std::nullopt;
}

void CommandGate::Sight(double now_s, const std::vector<LaneResult>& lanes) {
  last_sight_s_ = now_s;
  nearest_ahead_m_ = NearestDeadEnd(lanes, options_.corridor_half_width_m);
}

void CommandGate::Sight(double now_s, const std::vector<Eigen::Vector2f>& obstacles) {
  last_sight_s_ = now_s;
  nearest_ahead_m_ = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2f& p : obstacles) {
    if (p.x() > 0.0f && std::abs(p.y()) <= options_.corridor_half_width_m) {
      nearest_ahead_m_ = std::min(nearest_ahead_m_, static_cast<double>(p.x()));
    }
  }
}

void CommandGate::People(double now_s, const std::vector<Eigen::Vector2d>& people) {
  last_people_s_ = now_s;
  nearest_person_m_ = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : people) {
    if (p.x() > 0.0 && std::abs(std::atan2(p.y(), p.x())) <= options_.person_half_angle_rad) {
      nearest_person_m_ = std::min(nearest_person_m_, p.norm());
    }
  }
}

double CommandGate::NextExpiry(double now_s) const {
  double next = std::numeric_limits<double>::infinity();
  const auto watch = [&](double last_s, double timeout_s) {
    const double expiry = last_s + timeout_s;
    if (expiry >= now_s) next = std::min(next, expiry);
  };
  watch(last_odometry_s_, options_.odometry_timeout_s);
  watch(last_sight_s_, sight_timeout_s());
  if (options_.require_laser) watch(last_scan_s_, options_.laser_timeout_s);
  return next;
}

GateDecision CommandGate::Decide(double now_s, const TimedTwist* teleop, const TimedTwist* mission) {
  GateDecision out;
  if (now_s - last_odometry_s_ > options_.odometry_timeout_s) {
    out.mode = ControlMode::kStopped;
    out.reason = GateReason::kNoOdometry;
    return out;
  }
  if (down()) {
    out.mode = ControlMode::kStopped;
    out.reason = GateReason::kDeviceDown;
    return out;
  }
  if (cliff_) {
    out.mode = ControlMode::kStopped;
    out.reason = GateReason::kCliff;
    return out;
  }
  if (now_s - last_fault_s_ <= options_.fault_hold_s) {
    out.mode = ControlMode::kStopped;
    out.reason = GateReason::kProtectiveStop;
    return out;
  }
  const auto limit = [this](const Twist2& t) {
    return Twist2{std::clamp(t.linear_mps, -options_.max_linear_mps, options_.max_linear_mps),
                  std::clamp(t.angular_rps, -options_.max_angular_rps, options_.max_angular_rps)};
  };
  if (teleop != nullptr && now_s - teleop->stamp_s <= options_.teleop_deadman_s) {
    out.mode = ControlMode::kTeleop;
    out.twist = limit(teleop->twist);
  } else if (mission != nullptr && now_s - mission->stamp_s <= options_.mission_fresh_s) {
    out.mode = mission->docking ? ControlMode::kDocking : ControlMode::kMission;
    out.twist = limit(mission->twist);
  }
  if (out.twist.linear_mps * bump_direction_ > 0.0 && bumped(now_s)) {
    out.twist.linear_mps = 0.0;
    out.reason = bump_direction_ > 0 ? GateReason::kBumpedForward : GateReason::kBumpedBacking;
  }
  if (out.twist.linear_mps > 0.0) {
    // Forward: only as fast as stops before the nearest obstacle the camera sees, and not at all without sight.
    const bool fresh = now_s - last_sight_s_ <= sight_timeout_s();
    const double cap = !fresh ? 0.0
                       : out.mode == ControlMode::kDocking
                           ? options_.docking_max_mps
                           : SpeedForFreeDistance(nearest_ahead_m_ - options_.front_offset_m, options_.stopping);
    if (out.twist.linear_mps > cap) {
      out.twist.linear_mps = cap;
      out.reason = fresh                    ? GateReason::kSlowedForObstacle
                   : options_.require_depth ? GateReason::kNoDepth
                                            : GateReason::kNoLaser;
    }
    if (options_.require_laser && now_s - last_scan_s_ > options_.laser_timeout_s && out.twist.linear_mps > 0.0) {
      out.twist.linear_mps = 0.0;
      out.reason = GateReason::kNoLaser;
    }
  }
  const double person_cap = options_.person_speed_factor * options_.max_linear_mps;
  if (out.twist.linear_mps > person_cap && now_s - last_people_s_ <= options_.people_fresh_s &&
      nearest_person_m_ <= options_.person_near_m) {
    out.twist.linear_mps = person_cap;
    out.reason = GateReason::kSlowedForPerson;
  }
  if (out.twist.linear_mps != 0.0) last_moving_linear_mps_ = out.twist.linear_mps;
  return out;
}

}  // namespace corridor::nav
