#include "server/nodes/control_node.h"

#include <cmath>
#include <future>
#include <utility>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr double kLatencyPublishS = 0.5;
constexpr drivers::TimeNs kPastExpiryNs = 100'000;  // 0.1 ms

}  // namespace

ControlNode::ControlNode(Executor& executor, Bus& bus, drivers::DiffDriveBase& base,
                         const nav::CommandGateOptions& options, std::vector<drivers::DeviceLink*> pumped)
    : PeriodicNode("control", executor, bus, options.control_rate_hz),
      base_(base),
      pumped_(std::move(pumped)),
      gate_(options) {}

void ControlNode::Activate() {
  deadline_ = std::make_unique<DeadlineTimer>(executor(), [this] {
    Run("deadline", [this] {
      Act();
      Watch();
    });
  });
  Subscribe(topics::kOdometry, "odometry", [this](const auto& odometry) {
    const drivers::TimeNs now = clock().Now();
    gate_.Odometry(drivers::ToSeconds(now), odometry->bumper_pressed, odometry->cliff);
    if (odometry->bumper_pressed) bumped_topic_.Publish(Bumped{now, gate_.bumped_backing()});
    Watch();
  });
  Subscribe(topics::kGroundLanes, "sight", [this](const auto& ground) {
    // Fresh from when the frame arrived, not from when its lanes were ready: the gate's patience is the camera's.
    const double now_s = drivers::ToSeconds(ground->arrival_ns >= 0 ? ground->arrival_ns : clock().Now());
    if (!ground->lanes.empty()) {
      gate_.Sight(now_s, ground->lanes);
    } else {
      gate_.Sight(now_s, ground->obstacles);
    }
    Watch();
  });
  Subscribe(topics::kScan, "scan", [this](const auto&) {
    gate_.Scan(drivers::ToSeconds(clock().Now()));
    Watch();
  });
  // A native driver says its device stopped answering (or answers again): the robot stops at once, not at the tick.
  Subscribe(topics::kDeviceLinks, "link", [this](const auto& change) {
    gate_.Link(change->device, change->up);
    device_detail_[static_cast<int>(change->device)] = change->detail;
    Act();
  });
  Subscribe(topics::kDetections, "people", [this](const auto& detections) {
    std::vector<Eigen::Vector2d> people;
    for (const face::Detection& d : detections->items) {
      if (d.label == "person" && d.position) people.push_back(d.position->head<2>());
    }
    gate_.People(drivers::ToSeconds(clock().Now()), people);
  });
  Subscribe(topics::kFaults, "fault", [this](const auto& fault) {
    gate_.Fault(drivers::ToSeconds(clock().Now()));
    fault_detail_ = fault->node + " failed: " + fault->what;
    Act();
  });
  Subscribe(topics::kMissionCommand, "command", [this](const auto&) { Act(); });
  // A person's or a ROS 2 tool's velocity reaches the base at once, not at the next tick.
  Subscribe(topics::kTeleop, "teleop", [this](const auto&) { Act(); });
  PeriodicNode::Activate();
}

void ControlNode::Send(const nav::Twist2& twist) {
  base_.SetVelocity(twist);
  for (drivers::DeviceLink* link : pumped_) link->Pump();
}

void ControlNode::Stop(nav::GateReason reason, std::string detail) {
  Send({});
  bus()
      .Get(topics::kCmdVel)
      .Publish(BaseCommand{clock().Now(), {}, nav::ControlMode::kStopped, reason, std::move(detail)});
}

void ControlNode::OnFault() { Stop(nav::GateReason::kProtectiveStop, name() + " failed"); }

void ControlNode::Watch() {
  const double expiry = gate_.NextExpiry(drivers::ToSeconds(clock().Now()));
  // Just past it: at the expiry itself what it watches is still fresh.
  if (std::isfinite(expiry)) deadline_->At(drivers::FromSeconds(expiry) + kPastExpiryNs);
}

void ControlNode::Deactivate() {
  if (deadline_) deadline_->Stop();
  PeriodicNode::Deactivate();
  const auto stop = [this] { Stop(nav::GateReason::kShuttingDown, ""); };
  if (executor().schedule() == Schedule::kLockstep) {
    stop();
  } else {
    // On the control executor, behind any tick in flight, so that zero is the last command the base gets. If the
    // executor does not answer, stop from here anyway.
    auto done = std::make_shared<std::promise<void>>();
    executor().Post([stop, done] {
      stop();
      done->set_value();
    });
    if (done->get_future().wait_for(std::chrono::seconds(1)) != std::future_status::ready) stop();
  }
  SetHealth(Health::kInactive, "stopped for shutdown");
}

void ControlNode::Tick() { Act(); }

void ControlNode::Act() {
  const drivers::TimeNs now = clock().Now();
  const auto teleop = teleop_topic_.latest();
  const auto mission = mission_command_topic_.latest();
  std::optional<nav::TimedTwist> asked_teleop;
  std::optional<nav::TimedTwist> asked_mission;
  if (teleop) asked_teleop = nav::TimedTwist{teleop->twist, drivers::ToSeconds(teleop->received_ns)};
  if (mission && mission->active) {
    asked_mission = nav::TimedTwist{mission->twist, drivers::ToSeconds(mission->stamp_ns), mission->docking};
  }
  const nav::GateDecision decision = gate_.Decide(drivers::ToSeconds(now), asked_teleop ? &*asked_teleop : nullptr,
                                                  asked_mission ? &*asked_mission : nullptr);
  Send(decision.twist);
  const drivers::TimeNs sent_ns = clock().Now();
  if ((decision.mode == nav::ControlMode::kMission || decision.mode == nav::ControlMode::kDocking) &&
      mission->frame_arrival_ns >= 0 && mission->frame_arrival_ns != answered_frame_ns_) {
    answered_frame_ns_ = mission->frame_arrival_ns;
    latency_.Record(sent_ns, static_cast<double>(sent_ns - mission->frame_arrival_ns) * 1e-6);
  }
  if (sent_ns >= next_latency_publish_ns_) {
    next_latency_publish_ns_ = sent_ns + drivers::FromSeconds(kLatencyPublishS);
    const LatencyStats::Summary s = latency_.Summarise(sent_ns);
    control_latency_topic_.Publish(ControlLatency{s.rate_hz, s.p50_ms, s.p99_ms, s.max_ms, s.samples});
  }
  std::string detail;
  if (decision.reason == nav::GateReason::kProtectiveStop) detail = fault_detail_;
  if (decision.reason == nav::GateReason::kDeviceDown) detail = device_detail_[static_cast<int>(*gate_.down())];
  cmd_vel_topic_.Publish(BaseCommand{now, decision.twist, decision.mode, decision.reason, detail});
  if (decision.mode == nav::ControlMode::kStopped) {
    SetHealth(decision.reason == nav::GateReason::kProtectiveStop ? Health::kDegraded : Health::kError,
              StopReason(BaseCommand{now, {}, decision.mode, decision.reason, detail}));
  } else {
    SetHealth(Health::kOk, "");
  }
}

}  // namespace corridor::server
