// Messages that travel on the bus besides the drivers' own types, and their JSON form for the API and the
// WebSocket stream. A type with a ToJson overload here is visible as JSON wherever its topic is.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>

#include "drivers/battery.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "drivers/pan_servo.h"
#include "face/detect/detection.h"
#include "face/expression.h"
#include "nav/geometry/pose2.h"
#include "nav/geometry/sensor_view.h"
#include "nav/ground/morp.h"
#include "nav/localization/monte_carlo.h"
#include "nav/mission/mission_runner.h"
#include "nav/safety/command_gate.h"
#include "nav/safety/device_health.h"
#include "nav/tracking/moving_objects.h"
#include "server/runtime/fleet_order.h"

namespace corridor::server {

// A velocity request from a person or a building system, valid for the safety deadman from its arrival.
struct TeleopCommand {
  nav::Twist2 twist;
  drivers::TimeNs received_ns = 0;
  std::string source;  // "rest", "websocket", ...
};

// A pose with its time, in the map frame unless the topic says otherwise.
struct StampedPose {
  drivers::TimeNs stamp_ns = 0;
  nav::Pose2 pose;
};

// What the control loop sent to the base, and why (nav/safety/command_gate.h).
struct BaseCommand {
  drivers::TimeNs stamp_ns = 0;
  nav::Twist2 twist;
  nav::ControlMode mode = nav::ControlMode::kIdle;
  nav::GateReason reason = nav::GateReason::kNone;  // why it is not what was asked for
  std::string detail;                               // for a protective stop: what failed
};

// A node's callback threw (node.h): what failed, for the control node's protective stop and the console.
struct Fault {
  drivers::TimeNs stamp_ns = 0;
  std::string node;
  std::string loop;
  std::string what;
};

// A native driver says its device's link changed (drivers/serial/link_state.h): the command gate stops the robot
// while a device is not up.
struct DeviceLinkChange {
  drivers::TimeNs stamp_ns = 0;
  nav::Device device = nav::Device::kBase;
  bool up = true;
  std::string detail;  // "laser (rplidar on /dev/ttyUSB0): stale: no data for 52 ms"
};

// Each device's health (nav/safety/device_health.h), published a few times a second by the devices node.
struct DeviceReport {
  std::string device;  // base, laser, camera
  std::string driver;  // sim, dds, create2, rplidar
  std::string port;    // the serial device or the ROS 2 topic; empty for the simulator
  nav::DeviceState state = nav::DeviceState::kStale;
  double rate_hz = 0.0;  // data (odometry, scans, frames) a second
  double age_s = -1.0;   // since the last data; negative: none yet
  std::string link;      // a native driver's link state (running, stale, silent, ...); empty for the others
  std::uint64_t reconnects = 0;
  std::string last_error;      // the driver's last error; empty: none
  double handoff_cpu_s = 0.0;  // CPU time handing its data to the graph since the start (DeviceSlot's Handoff)
};
struct DevicesHealth {
  drivers::TimeNs stamp_ns = 0;
  std::vector<DeviceReport> devices;
};

// The bumper was pressed (published by the control node with every odometry that says so): which way the base was
// driving, that of the last moving command sent (a held zero command keeps the direction it bumped in).
struct Bumped {
  drivers::TimeNs stamp_ns = 0;  // the control node's clock
  bool backing = false;
};

// A velocity the mission wants, valid for a short time from its stamp (the control node's clock).
struct MissionCommand {
  drivers::TimeNs stamp_ns = 0;
  nav::Twist2 twist;
  bool active = true;                     // false: the mission is over (the control node stops and goes idle at once)
  drivers::TimeNs frame_arrival_ns = -1;  // the depth frame this command answers (host clock); -1: none
  bool docking = false;                   // onto or off a dock (nav/safety/command_gate.h)
};

// How fast the robot answers what its camera sees: depth frame arrival to base command, over the last few hundred
// frames, and how many frame-driven commands a second the control loop sends (the camera's rate when healthy).
struct ControlLatency {
  double rate_hz = 0.0;
  double p50_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
  std::uint64_t samples = 0;
};

// The mission in progress (or the last one), as the console and the API show it.
using MissionState = nav::MissionSnapshot;

// What missions ask of the building's doors (open, release), and what its controller says of each door.
struct DoorRequests {
  std::vector<nav::DoorRequest> requests;
};
struct DoorStates {
  nav::DoorReports doors;  // the doors asked for, by id
};

// What missions ask of the building's lifts (come to a floor, release), and what its controller says of each lift.
struct LiftRequests {
  std::vector<nav::LiftRequest> requests;
};
// A lift has brought the robot to another floor (the mission said so): that floor's map is to be the one in use, the
// robot at `pose` on it.
struct FloorArrival {
  std::string floor;
  nav::Pose2 pose;
};

struct LiftStates {
  nav::LiftReports lifts;  // the lifts in use, by id
};

// One local step of a mission on a depth frame (nav/policy/local_policy.h), and what the policy remembers of obstacles
// then (world frame): for traces and the console.
struct LocalStepState {
  drivers::TimeNs stamp_ns = 0;
  nav::LocalStep step;
  std::vector<Eigen::Vector2d> remembered;
};

// MORP's lanes for one depth frame (nav/ground/morp.h), and how long after the frame they were ready.
struct GroundLanes {
  drivers::TimeNs stamp_ns = 0;     // the frame's
  drivers::TimeNs arrival_ns = -1;  // the frame's arrival at the host
  std::uint64_t frame_sequence = 0;
  double latency_ms = 0.0;  // from the control executor taking the frame up to the lanes being ready
  std::vector<nav::LaneResult> lanes;
  // The same frame's depth scan (the nearest point of each column, base frame) and the floor it covers (base frame,
  // SensorView of the identity): the local navigator's obstacle memory keeps what the camera saw beside the lanes.
  std::vector<Eigen::Vector2d> scan;
  nav::SensorView scan_view;
  // With the voxel-reactive comparison policy, its front end's obstacle points (base frame) instead of lanes.
  std::vector<Eigen::Vector2f> obstacles;
};

// What the laser's moving-object tracker (nav/tracking) shows after one scan, in the map frame.
struct TrackedObjects {
  drivers::TimeNs stamp_ns = 0;     // the scan's
  drivers::TimeNs received_ns = 0;  // when the tracker took the scan, on the daemon's clock: its age for the mission
  nav::Surroundings surroundings;
};

// The simulator's people, as they are now (ground truth, for the console).
struct SimPedestrians {
  struct Person {
    Eigen::Vector2d position;
    Eigen::Vector2d velocity;
  };
  double radius_m = 0.0;
  std::vector<Person> people;
};

// Where localization puts the robot in the map, how sure it is, and a sample of its particles (for the console).
struct LocalizationState {
  drivers::TimeNs stamp_ns = 0;  // of the scan it last updated on
  std::string source;            // "odometry", "sim_truth" or "mcl"
  std::string sensor;            // what mcl reads: "laser" or "depth"
  double look_around_rps = 0.0;  // lost with the camera's narrow view: the robot should turn on the spot this fast
  nav::LocalizationEstimate estimate;
  std::vector<nav::Pose2> particles;  // at most 200
};

// A request to localization: take this pose (with its spread), search the whole map for the robot, map a new
// building (graph SLAM from where the robot is) and save the result under `name`, or hold on odometry alone (in a
// lift car, whose walls no map shows and whose floor changes under it) and resume the scans from where it holds.
struct LocalizationCommand {
  enum class Kind { kSetPose, kRelocalize, kStartMapping, kStopMapping, kHold, kResume };
  Kind kind = Kind::kSetPose;
  nav::Pose2 pose;
  double sigma_m = 0.2;
  double sigma_rad = 0.1;
  std::string name;  // kStartMapping: the new map's name
};

// Mapping a new building: the map as built so far (rendered every few seconds) and how the graph grows; after a
// stop, the map saved or why it could not be.
struct MappingState {
  drivers::TimeNs stamp_ns = 0;
  bool active = false;
  std::string name;  // of the map being built, or the last one built
  int scans = 0;
  int submaps = 0;
  int loop_closures = 0;
  std::shared_ptr<const nav::OccupancyGrid> grid;  // null before the first rendering
  std::uint64_t revision = 0;                      // bumped with every rendering
  std::string saved;                               // the last map saved to the library
  std::string error;                               // why the last stop could not save it (mapping goes on)
};

// The map the robot navigates on, with what belongs to it: its keep-out and slow zones, the doors a mission asks the
// building to open on it (none without a door controller), and the building's floors and lifts. Published whenever
// the map is switched or anything on it is edited; nodes that keep a copy of the map compare `grid` to see whether
// the map itself changed.
struct MapInUse {
  std::string name;
  std::shared_ptr<const nav::OccupancyGrid> grid;
  std::vector<nav::Zone> zones;
  std::vector<nav::Door> doors;
  nav::Building building;
};

// While exploring, the map being built, which the planner plans on instead of the map in use; a null grid: plan on
// the map in use (exploring is over).
struct ExploringMap {
  std::shared_ptr<const nav::OccupancyGrid> grid;
};

// Where people have been walking, per cell of `map` (nav::TrafficMap::StepCost), added to every plan's step costs
// while `map` is the map in use. A null cost: nobody has walked (missions do not reroute).
struct TrafficLayer {
  std::shared_ptr<const nav::OccupancyGrid> map;
  std::shared_ptr<const std::vector<float>> cost;
};

// Obstacles the map does not show (the 3D map's layer), per cell of `map`: obstacles in every costmap while `map` is
// the map in use.
struct ObstacleLayer {
  std::shared_ptr<const nav::OccupancyGrid> map;
  std::shared_ptr<const std::vector<std::int8_t>> cells;
};

// Explore the map being built (mapping is under way, or was just started by whoever asked).
struct ExploreCommand {
  std::string origin;  // who asked: "rest", ...
};

// Whether the robot is exploring (ExploreNode).
struct ExploreState {
  bool exploring = false;
};

// The face's current expression, and the last thing the robot said (said_sequence counts up with every phrase, so a
// subscriber that sees a new one speaks it once).
struct FaceState {
  face::Expression expression = face::Expression::kNeutral;
  double gaze_rad = 0.0;            // where the eyes look, from straight ahead, counter-clockwise (left)
  bool gaze_at_person = false;      // at a person detected, else the way the robot turns
  std::uint64_t said_sequence = 0;  // 0: nothing said yet
  std::string said;                 // the phrase's text
  std::string said_kind;            // greeting, excuse_me, arrived, or request (an app's `say`)
};

// People and objects detected in the camera (face/detect), built-in and pushed in, each with its track id; positions
// in the base frame at stamp_ns.
struct Detections {
  drivers::TimeNs stamp_ns = 0;
  std::vector<face::Detection> items;
};

// Detections an external detector pushed in (POST /api/v1/detections, handed to PerceptionNode::Push): kept for ttl_s
// from received_ns under their source's name; a new push from the same source replaces them.
struct ExternalDetections {
  std::string source;
  double ttl_s = 2.0;
  drivers::TimeNs received_ns = 0;
  std::vector<face::Detection> items;
};

// An app's or building system's request to the face (POST /api/v1/face): show an expression for hold_s, say a phrase,
// or both.
struct FaceCommand {
  std::optional<face::Expression> expression;
  double hold_s = 5.0;
  std::string say;  // empty: nothing to say
};

nlohmann::json ToJson(const ControlLatency& latency);
nlohmann::json ToJson(const drivers::BatteryState& battery);
nlohmann::json ToJson(const FleetOrder& order);
nlohmann::json ToJson(const LocalizationState& localization);
nlohmann::json ToJson(const FaceState& face);
nlohmann::json ToJson(const face::Detection& detection);
nlohmann::json ToJson(const Detections& detections);
nlohmann::json ToJson(const SimPedestrians& pedestrians);
nlohmann::json ToJson(const TrackedObjects& tracked);  // the objects only, not the static points
nlohmann::json ToJson(const GroundLanes& lanes);
nlohmann::json ToJson(const MissionState& mission);
nlohmann::json ToJson(const LocalStepState& step);
nlohmann::json ToJson(const nav::Pose2& pose);
nlohmann::json ToJson(const nav::Twist2& twist);
nlohmann::json ToJson(const StampedPose& pose);
nlohmann::json ToJson(const drivers::WheelOdometry& odometry);
nlohmann::json ToJson(const drivers::LaserScan& scan);
nlohmann::json ToJson(const TeleopCommand& command);
nlohmann::json ToJson(const BaseCommand& command);
nlohmann::json ToJson(const Fault& fault);
nlohmann::json ToJson(const DevicesHealth& health);
// What the console and the API show as the reason the command is not what was asked ("" when it is).
std::string StopReason(const BaseCommand& command);

}  // namespace corridor::server
