// The control loop: picks the command for the base (teleop over a mission over standing still), applies the
// safety limits and watchdogs, and sends it. Stops the robot when the teleop deadman lapses, when the base's
// odometry stops arriving (the base is not answering), and when the node is deactivated (shutdown). While the
// bumper is pressed, and for a second after, nothing drives on in the direction the robot bumped in (turning and
// driving away are allowed).
//
// It decides on a timer (control_rate_hz, the watchdogs' clock) and at once whenever the mission sends a command,
// which it does once per depth frame: the robot answers a frame without waiting for the next tick. The latency
// from a frame's arrival to the base command that answers it is published on control/latency.
#pragma once

#include <atomic>

#include "drivers/diff_drive_base.h"
#include "server/runtime/bus.h"
#include "server/runtime/config.h"
#include "server/runtime/latency_stats.h"
#include "server/runtime/node.h"

namespace corridor::server {

// The pure decision of one control tick, separate from the node for tests.
struct ControlInputs {
  drivers::TimeNs now_ns = 0;
  const TeleopCommand* teleop = nullptr;     // the latest, or null
  drivers::TimeNs last_odometry_ns = -1;     // arrival time (the node's clock) of the latest odometry; -1 never
  const MissionCommand* mission = nullptr;   // the latest, or null
  const GroundLanes* lanes = nullptr;        // the latest, or null
  drivers::TimeNs last_lanes_ns = -1;        // arrival time of the latest lanes; -1 never
  drivers::TimeNs last_bump_ns = -1;         // arrival time of the latest odometry with the bumper pressed
  int bump_direction = 1;                    // +1 it bumped driving forward, -1 backing
};
BaseCommand DecideCommand(const ControlInputs& in, const SafetyOptions& options);

class ControlNode final : public PeriodicNode {
 public:
  ControlNode(Executor& executor, Bus& bus, drivers::DiffDriveBase& base, const drivers::Clock& clock,
              const SafetyOptions& options);
  void Activate() override;
  // Stops the timer and commands zero velocity: the first thing shutdown does.
  void Deactivate() override;

 private:
  void Tick() override;
  void Act();  // one decision, sent to the base

  Bus& bus_;
  drivers::DiffDriveBase& base_;
  SafetyOptions options_;
  std::atomic<drivers::TimeNs> last_odometry_ns_{-1};
  std::atomic<drivers::TimeNs> last_lanes_ns_{-1};
  std::atomic<drivers::TimeNs> last_bump_ns_{-1};
  std::atomic<int> bump_direction_{1};
  // On the control executor only:
  LatencyStats latency_;
  drivers::TimeNs answered_frame_ns_ = -1;  // arrival of the last frame a command answered
  drivers::TimeNs next_latency_publish_ns_ = 0;
};

}  // namespace corridor::server
