#include "server/nodes/control_node.h"

#include <algorithm>
#include <limits>
#include <future>

#include "server/runtime/topics.h"

namespace corridor::server {

namespace {

// A mission command older than this is not acted on: the mission node has stopped talking.
constexpr double kMissionFreshS = 0.3;
constexpr double kLatencyPublishS = 0.5;
// After the bumper is released, forward motion waits this long: the mission has time to turn away from what it
// touched instead of pushing on at once.
constexpr double kBumpHoldS = 1.0;

nav::Twist2 Limit(const nav::Twist2& t, const SafetyOptions& o) {
  return {std::clamp(t.linear_mps, -o.max_linear_mps, o.max_linear_mps),
          std::clamp(t.angular_rps, -o.max_angular_rps, o.max_angular_rps)};
}

}  // namespace

BaseCommand DecideCommand(const ControlInputs& in, const SafetyOptions& options) {
  BaseCommand out{.stamp_ns = in.now_ns, .twist = {}, .mode = "idle", .reason = ""};
  if (in.last_odometry_ns < 0 || in.now_ns - in.last_odometry_ns > drivers::FromSeconds(options.odometry_timeout_s)) {
    out.mode = "stopped";
    out.reason = "no odometry from the base";
    return out;
  }
  if (in.teleop != nullptr && in.now_ns - in.teleop->received_ns <= drivers::FromSeconds(options.teleop_deadman_s)) {
    out.mode = "teleop";
    out.twist = Limit(in.teleop->twist, options);
  } else if (in.mission != nullptr && in.mission->active &&
             in.now_ns - in.mission->stamp_ns <= drivers::FromSeconds(kMissionFreshS)) {
    out.mode = "mission";
    out.twist = Limit(in.mission->twist, options);
  }
  if (out.twist.linear_mps * in.bump_direction > 0.0 && in.last_bump_ns >= 0 &&
      in.now_ns - in.last_bump_ns <= drivers::FromSeconds(kBumpHoldS)) {
    out.twist.linear_mps = 0.0;
    out.reason = in.bump_direction > 0 ? "bumper pressed: not driving forward" : "bumper pressed: not backing";
  }
  if (out.twist.linear_mps > 0.0) {
    // Forward: only as fast as stops before the nearest dead-end the camera sees, and not at all without sight.
    const bool fresh = in.lanes != nullptr && in.last_lanes_ns >= 0 &&
                       in.now_ns - in.last_lanes_ns <= drivers::FromSeconds(options.depth_timeout_s);
    const double nearest =
        fresh ? nav::NearestDeadEnd(in.lanes->lanes, options.corridor_half_width_m) : std::numeric_limits<double>::infinity();
    const double cap = fresh ? nav::SpeedForFreeDistance(nearest - options.front_offset_m, options.stopping) : 0.0;
    if (out.twist.linear_mps > cap) {
      out.twist.linear_mps = cap;
      out.reason = fresh ? "slowed for an obstacle ahead" : "no depth frames: not driving forward";
    }
  }
  return out;
}

ControlNode::ControlNode(Executor& executor, Bus& bus, drivers::DiffDriveBase& base, const drivers::Clock& clock,
                         const SafetyOptions& options)
    : PeriodicNode("control", executor, clock, options.control_rate_hz), bus_(bus), base_(base), options_(options) {}

void ControlNode::Activate() {
  bus_.Get(topics::kOdometry).Subscribe(executor(), [this](const auto& odometry) {
    last_odometry_ns_ = clock().Now();
    if (odometry->bumper_pressed) {
      last_bump_ns_ = clock().Now();
      // The way it bumped: that of the command last sent (none while held: the direction stays).
      const auto sent = bus_.Get(topics::kCmdVel).latest();
      if (sent && sent->twist.linear_mps != 0.0) bump_direction_ = sent->twist.linear_mps > 0.0 ? 1 : -1;
      bus_.Get(topics::kBumped).Publish(Bumped{last_bump_ns_.load(), bump_direction_ < 0});
    }
  });
  bus_.Get(topics::kGroundLanes).Subscribe(executor(), [this](const auto&) { last_lanes_ns_ = clock().Now(); });
  bus_.Get(topics::kMissionCommand).Subscribe(executor(), [this](const auto&) { Act(); });
  PeriodicNode::Activate();
}

void ControlNode::Deactivate() {
  PeriodicNode::Deactivate();
  const auto stop = [this] {
    base_.SetVelocity({});
    bus_.Get(topics::kCmdVel).Publish(BaseCommand{clock().Now(), {}, "stopped", "shutting down"});
  };
  // On the control executor, behind any tick in flight, so that zero is the last command the base gets. If the
  // executor does not answer, stop from here anyway.
  auto done = std::make_shared<std::promise<void>>();
  executor().Post([stop, done] {
    stop();
    done->set_value();
  });
  if (done->get_future().wait_for(std::chrono::seconds(1)) != std::future_status::ready) stop();
  SetHealth(Health::kInactive, "stopped for shutdown");
}

void ControlNode::Tick() { Act(); }

void ControlNode::Act() {
  const auto teleop = bus_.Get(topics::kTeleop).latest();
  const auto mission = bus_.Get(topics::kMissionCommand).latest();
  const auto lanes = bus_.Get(topics::kGroundLanes).latest();
  const BaseCommand command = DecideCommand(
      {clock().Now(), teleop.get(), last_odometry_ns_.load(), mission.get(), lanes.get(), last_lanes_ns_.load(),
       last_bump_ns_.load(), bump_direction_.load()},
      options_);
  base_.SetVelocity(command.twist);
  const drivers::TimeNs sent_ns = clock().Now();
  if (command.mode == "mission" && mission->frame_arrival_ns >= 0 && mission->frame_arrival_ns != answered_frame_ns_) {
    answered_frame_ns_ = mission->frame_arrival_ns;
    latency_.Record(sent_ns, static_cast<double>(sent_ns - mission->frame_arrival_ns) * 1e-6);
  }
  if (sent_ns >= next_latency_publish_ns_) {
    next_latency_publish_ns_ = sent_ns + drivers::FromSeconds(kLatencyPublishS);
    const LatencyStats::Summary s = latency_.Summarise(sent_ns);
    bus_.Get(topics::kControlLatency).Publish(ControlLatency{s.rate_hz, s.p50_ms, s.p99_ms, s.max_ms, s.samples});
  }
  bus_.Get(topics::kCmdVel).Publish(command);
  if (command.mode == "stopped") {
    SetHealth(Health::kError, command.reason);
  } else {
    SetHealth(Health::kOk, "");
  }
}

}  // namespace corridor::server
