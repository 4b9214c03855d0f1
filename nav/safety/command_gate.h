// The command gate: the last word on every velocity sent to the base. It picks the command (a person's teleop over a
// mission over standing still), applies the robot's limits, and stops or slows the robot whenever it is unsure:
//   - no odometry from the base for odometry_timeout_s (the base is not answering): stop;
//   - a device whose driver says it stopped answering or is gone (native drivers watch their links byte by byte):
//     stop until it is back;
//   - the base reports a cliff or a dropped wheel: stop;
//   - a protective stop for fault_hold_s after any part of the daemon failed (a node's callback threw): stop;
//   - while the bumper is pressed and bump_hold_s after, nothing drives on in the direction the robot bumped in
//     (turning and driving away are allowed);
//   - forward only as fast as stops before the nearest obstacle the depth camera sees in the robot's way (the
//     stopping model, from the front of the robot), and not at all without a depth frame for depth_timeout_s, nor,
//     on a robot with a laser, without a scan for laser_timeout_s; on a robot without a camera the laser's lanes
//     stand in for the camera's (sight then goes stale after laser_timeout_s);
//   - docking (a mission command that says so) drives up to the dock's face, which the camera sees as an obstacle:
//     forward is capped at docking_max_mps instead, still only with fresh depth frames and with the bumper's rule.
// Pure logic: the caller reports what arrived and when (seconds on one clock), and asks for a decision.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/ground/morp.h"
#include "nav/safety/stopping.h"

namespace corridor::nav {

enum class ControlMode { kIdle, kTeleop, kMission, kDocking, kStopped };
const char* ToString(ControlMode mode);

// Why the command is not what was asked for (kNone: it is).
enum class GateReason {
  kNone,
  kNoOdometry,      // the base is not answering
  kProtectiveStop,  // a part of the daemon failed
  kShuttingDown,
  kBumpedForward,      // bumper pressed: not driving forward
  kBumpedBacking,      // bumper pressed: not backing
  kSlowedForObstacle,  // forward speed capped by what the camera sees ahead
  kNoDepth,            // no fresh depth frame: not driving forward
  kSlowedForPerson,    // forward speed capped near a person ahead
  kNoLaser,            // no fresh laser scan: not driving forward
  kCliff,              // the base sees no floor under it, or a wheel dropped
  kDeviceDown,         // a device's driver says it stopped answering or is gone
};
const char* ToString(GateReason reason);

struct CommandGateOptions {
  double teleop_deadman_s = 0.5;  // a teleop command stops mattering this long after it arrived
  double max_linear_mps = 0.5;    // limits on every command sent to the base
  double max_angular_rps = 1.5;
  double odometry_timeout_s = 0.08;    // no odometry for this long: the base is not answering; stop
  double control_rate_hz = 50.0;       // the watchdogs' tick (the node's; missions also command on every frame)
  double depth_timeout_s = 0.08;       // depth frames older than this are stale
  double laser_timeout_s = 0.3;        // with a laser (require_laser), scans older than this are stale
  bool require_laser = false;          // the robot has a laser: its scans must be fresh to drive forward
  bool require_depth = true;           // the robot has a depth camera (else sight comes from the laser's lanes)
  double front_offset_m = 0.2;         // from the base's centre to its front
  double corridor_half_width_m = 0.3;  // what lies this close to the centre line is in the robot's way
  StoppingModel stopping{.max_decel_mps2 = 0.8, .reaction_time_s = 0.1, .margin_m = 0.05};
  double mission_fresh_s = 0.3;   // a mission command older than this is not acted on
  double bump_hold_s = 1.0;       // after the bumper is released, driving on that way waits this long
  double fault_hold_s = 2.0;      // the protective stop after a fault
  double docking_max_mps = 0.12;  // forward while docking
  // Near people: a person detected ahead (within person_half_angle_rad of straight ahead) within person_near_m caps
  // forward speed at person_speed_factor x max_linear_mps, while the report is at most people_fresh_s old.
  double person_near_m = 1.5;
  double person_half_angle_rad = 0.7854;
  double person_speed_factor = 0.5;
  double people_fresh_s = 1.0;
};

// The devices whose links the gate watches (their drivers say when they go down).
enum class Device { kBase, kLaser, kCamera };
inline constexpr int kDeviceCount = 3;
const char* ToString(Device device);

// A velocity someone asks for, and when (seconds, the gate's clock).
struct TimedTwist {
  Twist2 twist;
  double stamp_s = 0.0;
  bool docking = false;  // a mission's command onto a dock (see above)
};

struct GateDecision {
  Twist2 twist;
  ControlMode mode = ControlMode::kIdle;
  GateReason reason = GateReason::kNone;
};

class CommandGate {
 public:
  explicit CommandGate(const CommandGateOptions& options) : options_(options) {}

  // Odometry arrived at now_s; the bumper was pressed or not; the base sees a cliff (or a wheel dropped) or not. A
  // press is taken to be in the direction of the last moving command the gate let through.
  void Odometry(double now_s, bool bumper_pressed, bool cliff = false);
  // A laser scan arrived.
  void Scan(double now_s) { last_scan_s_ = now_s; }
  // A device's driver says its device is answering (up) or not (stopped answering, unplugged).
  void Link(Device device, bool up) { down_[static_cast<int>(device)] = !up; }
  // The first device that is down, if any.
  std::optional<Device> down() const;
  // A depth frame's lanes arrived (MORP), or the obstacle points of another front end (base frame, x forward).
  void Sight(double now_s, const std::vector<LaneResult>& lanes);
  void Sight(double now_s, const std::vector<Eigen::Vector2f>& obstacles);
  // The people detected now (their positions in the base frame, metres).
  void People(double now_s, const std::vector<Eigen::Vector2d>& people);
  // Some part of the daemon failed at now_s: protective stop.
  void Fault(double now_s) { last_fault_s_ = now_s; }

  // The next moment after now_s at which something watched goes stale (odometry, sight, scans) and a decision may
  // change with nothing arriving; +infinity when nothing is fresh. The caller decides again then.
  double NextExpiry(double now_s) const;

  // The command for the base at now_s, from the latest teleop and mission requests (null: none). `mission` counts
  // only while active.
  GateDecision Decide(double now_s, const TimedTwist* teleop, const TimedTwist* mission);

  // True while a pressed bumper holds the robot; backing tells which way it bumped.
  bool bumped(double now_s) const { return now_s - last_bump_s_ <= options_.bump_hold_s; }
  bool bumped_backing() const { return bump_direction_ < 0; }
  const CommandGateOptions& options() const { return options_; }

 private:
  static constexpr double kNever = -std::numeric_limits<double>::infinity();

  double sight_timeout_s() const {
    return options_.require_depth ? options_.depth_timeout_s : options_.laser_timeout_s;
  }

  CommandGateOptions options_;
  double last_odometry_s_ = kNever;
  bool cliff_ = false;
  double last_scan_s_ = kNever;
  std::array<bool, kDeviceCount> down_{};
  double last_bump_s_ = kNever;
  int bump_direction_ = 1;  // +1 forward, -1 backing
  double last_sight_s_ = kNever;
  double nearest_ahead_m_ = std::numeric_limits<double>::infinity();
  double last_fault_s_ = kNever;
  double last_people_s_ = kNever;
  double nearest_person_m_ = std::numeric_limits<double>::infinity();  // ahead, in the last report
  double last_moving_linear_mps_ = 0.0;  // the last command with linear speed the gate let through
};

}  // namespace corridor::nav
