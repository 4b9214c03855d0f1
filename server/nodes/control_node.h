// The control loop: feeds the command gate (nav/safety/command_gate.h) with what arrives on the bus and sends its
// decision to the base. It decides on a timer (safety.control_rate_hz), at once whenever the mission sends a command,
// which it does once per depth frame (the robot answers a frame without waiting for the next tick), and the moment
// a watchdog's timeout runs out (odometry, sight, scans: a silent device stops the robot at its timeout, not up to
// a tick later). The latency from a frame's arrival to the base command that answers it is published on
// control/latency; each bump on safety/bumped with the way the base was driving; a fault of any node (safety/faults)
// puts the robot in a protective stop; a device whose native driver says it went down (devices/links) stops the robot
// at once. After every decision it pumps the native drivers (ros2_control's read and write around its update): what
// their devices sent is taken and handed on, and the decision written to the wheels at once, on the control loop's
// own wake-ups. On deactivation (shutdown) it commands zero velocity last.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "drivers/diff_drive_base.h"
#include "drivers/serial/link_state.h"
#include "nav/safety/command_gate.h"
#include "server/runtime/bus.h"
#include "server/runtime/latency_stats.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class ControlNode final : public PeriodicNode {
 public:
  // `pumped`: the native drivers' links, pumped after every decision (drivers/serial/linked_device.h).
  ControlNode(Executor& executor, Bus& bus, drivers::DiffDriveBase& base, const nav::CommandGateOptions& options,
              std::vector<drivers::DeviceLink*> pumped = {});
  void Activate() override;
  // Stops the timer and commands zero velocity: the first thing shutdown does.
  void Deactivate() override;

 private:
  void Tick() override;
  void Act();    // one decision, sent to the base
  void Watch();  // the deadline timer set at the gate's next expiry
  // Zero velocity to the base at once, and on cmd_vel with `reason`.
  void Stop(nav::GateReason reason, std::string detail);
  // `twist` to the base, and the native drivers pumped.
  void Send(const nav::Twist2& twist);
  void OnFault() override;  // this node's own callback failed: stop from here

  drivers::DiffDriveBase& base_;
  std::vector<drivers::DeviceLink*> pumped_;
  // On the control executor only:
  nav::CommandGate gate_;
  std::unique_ptr<DeadlineTimer> deadline_;                   // while active
  std::string fault_detail_;                                  // the latest fault, for the protective stop's reason
  std::array<std::string, nav::kDeviceCount> device_detail_;  // each device's latest link change, for the stop's reason
  LatencyStats latency_;
  drivers::TimeNs answered_frame_ns_ = -1;  // arrival of the last frame a command answered
  drivers::TimeNs next_latency_publish_ns_ = 0;

  // The topics it reads and writes, resolved once.
  Topic<Bumped>& bumped_topic_ = bus().Get(topics::kBumped);
  Topic<BaseCommand>& cmd_vel_topic_ = bus().Get(topics::kCmdVel);
  Topic<ControlLatency>& control_latency_topic_ = bus().Get(topics::kControlLatency);
  Topic<MissionCommand>& mission_command_topic_ = bus().Get(topics::kMissionCommand);
  Topic<TeleopCommand>& teleop_topic_ = bus().Get(topics::kTeleop);
};

}  // namespace corridor::server
