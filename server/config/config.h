// corridord's configuration: one options struct per module, filled from one YAML file by LoadConfig, which is
// strict (see ConfigReader). config/corridor.yaml in the tree documents every key.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "drivers/create2/create2_options.h"
#include "drivers/dds/device_options.h"
#include "drivers/dynamixel/pan_servo_options.h"
#include "drivers/hokuyo/hokuyo_options.h"
#include "drivers/kobuki/kobuki_options.h"
#include "drivers/lds/lds_options.h"
#include "drivers/openni2/openni2_options.h"
#include "drivers/realsense/realsense_options.h"
#include "drivers/rplidar/rplidar_options.h"
#include "drivers/serial_text/serial_text_options.h"
#include "drivers/sim/sim_robot.h"
#include "drivers/sim/world.h"
#include "drivers/stereo/stereo_options.h"
#include "drivers/turtlebot3/turtlebot3_options.h"
#include "face/detect/depth_people.h"
#include "face/detect/dnn_detector.h"
#include "face/detect/face_cascade.h"
#include "face/detect/hog_people.h"
#include "face/detect/people_detector.h"
#include "face/detect/simulated_people.h"
#include "face/detect/tracker.h"
#include "face/events.h"
#include "face/expression.h"
#include "face/speech.h"
#include "nav/ground/afds.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/morp.h"
#include "nav/ground/multi_view.h"
#include "nav/localization/monte_carlo.h"
#include "nav/mapping/occupancy_octree.h"
#include "nav/mission/mission_runner.h"
#include "nav/planner/costmap.h"
#include "nav/policy/gaze.h"
#include "nav/policy/local_navigator.h"
#include "nav/safety/command_gate.h"
#include "nav/tracking/moving_objects.h"
#include "nav/tracking/traffic_map.h"
#include "server/auth/options.h"
#include "server/config/config_reader.h"  // ConfigError

namespace corridor::server {

// HTTPS and WSS on server.port; without a certificate configured, a self-signed one is made in the state directory.
struct TlsOptions {
  bool enabled = false;
  std::filesystem::path certificate;  // PEM; empty: <state_dir>/tls/certificate.pem, made on first start
  std::filesystem::path key;          // PEM, the certificate's private key
  int redirect_port = 0;              // plain HTTP here only redirects to HTTPS; 0: none
};

struct ServerOptions {
  int port = 8080;  // 0 picks a free port (logged at start-up)
  std::string bind_address = "0.0.0.0";
  std::filesystem::path web_root;        // the built console; empty: next to the binary or in the source tree
  int max_body_bytes = 4 * 1024 * 1024;  // larger request bodies get 413 (a whole map image fits)
  double stream_rate_hz = 20.0;          // WebSocket state pushes per second
  TlsOptions tls;
};

struct StoreOptions {
  std::filesystem::path state_dir = "/var/lib/corridor";
};

struct MapOptions {
  // A ROS map_server YAML. Empty: the simulator's world when it is a map, else its collision slice.
  std::filesystem::path file;
};

// safety: the command gate's options (nav/safety/command_gate.h).
using SafetyOptions = nav::CommandGateOptions;

// The simulator (the robot's devices when devices.base.driver is sim).
struct SimulatorOptions {
  std::filesystem::path world;  // .yaml map, .world/.sdf, or a mesh file
  drivers::sim::WorldOptions world_options;
  drivers::sim::SimOptions robot;
  // Things the map does not show: obstacles standing on the floor, and people walking back and forth (ORCA among
  // themselves, blind to the robot) on random routes within pedestrians_within_m of the start.
  std::vector<drivers::sim::StaticObstacle> obstacles;
  int pedestrians = 0;
  double pedestrians_within_m = 8.0;
};

// The laser's moving-object tracker (nav/tracking); without a laser it has nothing to do.
struct TrackingOptions {
  bool enabled = true;
  bool camera = true;  // without a laser, track people in the depth camera's view (docs/benchmarks.md)
  nav::MovingObjectOptions objects;
  nav::TrafficOptions traffic;  // where people walk, for the planner (weight 0: not used)
};

// planner: nav::CostmapOptions; mission: nav::MissionRunnerOptions (the local policy, the
// navigator's and the follower's fields at the top, MORP-RB's under avoid, evasion's under evade; their fields are the
// keys, with units).

// Where the robot's pose in the map comes from: its wheel odometry placed at the start pose (dead reckoning, until
// map-based localization lands), or, in the simulator only, the simulator's ground truth (the scenario runner: it
// measures local navigation, as DPoom's evaluation does).
struct LocalizationOptions {
  // odometry: wheel odometry from the start pose (it drifts); sim_truth: the simulator's truth; mcl: Monte Carlo
  // localization in the active map from the laser's scans (nav/localization/monte_carlo.h).
  enum class Source { kOdometry, kSimTruth, kMonteCarlo };
  Source source = Source::kOdometry;
  nav::MonteCarloOptions mcl;
  std::uint64_t seed = 1;        // of the particle filter
  double initial_sigma_m = 0.1;  // the start pose's spread
  double initial_sigma_deg = 5.0;
  double relocalize_every_s = 2.0;  // while lost, a global search this often
  // Without a laser, the depth camera's scan: its columns' nearest obstacles out to this range (farther, depth noise
  // puts walls off the map). The image's sides are kept: a wall cut by them is still the map's wall.
  // Without a laser: lost after this many depth scans in a row that agree less than well with the map (0: never).
  int depth_doubtful_scans = 30;
  nav::DepthScanOptions depth = [] {
    nav::DepthScanOptions o;
    o.segment_gap_m = 0.0;
    o.average_within_m = 0.15;  // the wall's mean, not its nearest noisy pixel
    return o;
  }();
};

// The 3D map (server/nodes/octree_node.h): a depth frame every insert_every_s at the estimated pose; what stands
// between min_height_m and max_height_m (the step the robot drives over and its own height) is an obstacle for the
// planner.
struct OctreeOptions {
  bool enabled = true;
  nav::OccupancyOctreeOptions octree = [] {
    nav::OccupancyOctreeOptions o;
    o.project_min_probability = 0.9;  // people walking past stay out of the planner's layer
    return o;
  }();
  double insert_every_s = 1.0;
  double min_height_m = 0.1;
  double max_height_m = 1.2;
  bool costmap_layer = true;
  double update_every_s = 2.0;  // the layer and the API's snapshot, when the octree changed
  double save_every_s = 30.0;
};

// The robot's face (server/nodes/face_node.h): when it changes expression, what it says, and its voice.
struct FaceOptions {
  face::ExpressionOptions expression;
  face::EventOptions events;  // what building systems are told (face/events.h)
  bool mute = false;          // say nothing aloud (the page's mouth still moves with what is said)
  face::SpeechOptions voice;
};

// People and faces in the camera (server/nodes/perception_node.h), and what the robot does about them.
struct PerceptionOptions {
  bool enabled = true;
  // auto: the simulated people with the simulator, hog on a real camera; sim; hog (HOG alone); people (HOG, head and
  // shoulders and faces: face/detect/people_detector.h; finds more, five times the cost); dnn (the user's model).
  enum class Detector { kAuto, kSimulated, kHog, kPeople, kDnn };
  Detector detector = Detector::kAuto;
  bool faces = true;           // also the frontal face cascade (a face turned to the robot: a person looking at it)
  double rate_hz = 5.0;        // detections a second, on the perception executor
  face::HogOptions hog;        // for hog, and people's own HOG
  face::PeopleOptions people;  // its hog is `hog`
  // With an image detector (hog, people, dnn) and a depth image: an object the tracker follows that the depth image
  // shows person-shaped (face/detect/depth_people.h) is a person too, where the image's detector saw none.
  bool depth_people = true;
  face::DepthPeopleOptions depth;
  face::FaceCascadeOptions face_cascade;
  face::DnnOptions dnn;
  face::SimulatedPeopleOptions sim;
  face::TrackerOptions tracker;
  double max_ttl_s = 10.0;  // the longest an external detection may be kept
};

// Webhooks (server/api/webhooks.h): how the robot's events are delivered to the building systems that subscribed.
struct WebhookOptions {
  double timeout_s = 5.0;      // one attempt: connect, send, answer
  int max_attempts = 8;        // then the delivery has failed
  double first_retry_s = 2.0;  // the wait before the second attempt, doubled for each next one
  double max_retry_s = 300.0;  // the longest wait between two attempts
  int keep_deliveries = 100;   // finished deliveries kept per webhook
  int max_pending = 200;       // undelivered ones per webhook; beyond, the oldest fails (the receiver is gone)
  std::string ca_file;         // HTTPS: trust these certificates (PEM) besides the system's
  std::string robot;           // the robot's name in every payload; empty: the host name
};

// VDA 5050 over MQTT (server/nodes/vda5050_node.h): a master control's orders and instant actions.
struct Vda5050Options {
  std::string broker;                   // mqtt://host:port; empty: off
  std::string interface_name = "uagv";  // topics: interface_name/v2/manufacturer/serial_number/<topic>
  std::string manufacturer = "corridor";
  std::string serial_number;       // empty: the robot's name (webhooks.robot, else the host name)
  int qos = 0;                     // order, instantActions, state, visualization, factsheet (connection: 1)
  double state_interval_s = 30.0;  // the state at least this often, and on every change
  double visualization_hz = 1.0;
};

struct FleetOptions {
  Vda5050Options vda5050;
};

// One HTTP request to a building system; "{door}" in the URL and the body is replaced by the door's id.
struct HttpRequestTemplate {
  std::string method = "POST";
  std::string url;   // empty: not sent
  std::string body;  // sent as application/json when not empty
};

// A building system that speaks Open-RMF's door or lift messages over MQTT (server/fleet/rmf_mqtt.h).
struct RmfMqttOptions {
  std::string broker;                     // mqtt://host:port; empty: not used
  std::string prefix = "rmf";             // topics: prefix/door_requests, prefix/door_states, ...
  std::string requester_id = "corridor";  // DoorRequest.requester_id, LiftRequest.session_id
};

// The building's door controller, spoken to over HTTP (server/fleet/doors.h): `open` asks a door to open (2xx:
// taken; another 4xx: refused, the answer's body saying why), `state` is polled every poll_s until the door is open
// (its JSON answer's value at open_pointer equals open_value), `release` says the robot is through.
struct DoorControllerOptions {
  HttpRequestTemplate open;
  HttpRequestTemplate state{"GET", "", ""};
  std::string open_pointer = "/state";  // JSON pointer into the state's answer
  std::string open_value = "open";
  HttpRequestTemplate release;
  std::vector<std::pair<std::string, std::string>> headers;  // sent with each (Authorization, say)
  double poll_s = 0.5;
  double request_timeout_s = 5.0;  // one HTTP exchange
  RmfMqttOptions mqtt;             // instead of HTTP: Open-RMF's DoorRequest and DoorState over MQTT
  bool configured() const { return !open.url.empty() || !mqtt.broker.empty(); }
};

// A door on a map: a line across a passage.
struct DoorPlace {
  std::string id;
  std::string map;
  Eigen::Vector2d from = Eigen::Vector2d::Zero();
  Eigen::Vector2d to = Eigen::Vector2d::Zero();
};

struct DoorsOptions {
  DoorControllerOptions controller;
  std::vector<DoorPlace> list;  // the simulator's doors are added for its world's map
};

// The building's lift controller, spoken to over HTTP (server/fleet/lifts.h): `call` asks a lift to come to a floor
// and open its door there ("{lift}" and "{floor}" filled in; 2xx: taken; another 4xx: refused, the body saying why),
// `state` is polled every poll_s while the robot uses the lift (its JSON answer's values at floor_pointer, and at
// door_pointer equal to door_open_value when the door is open), `release` says the robot is done with it.
struct LiftControllerOptions {
  HttpRequestTemplate call{"PUT", "", ""};
  HttpRequestTemplate state{"GET", "", ""};
  std::string floor_pointer = "/floor";
  std::string door_pointer = "/door";
  std::string door_open_value = "open";
  HttpRequestTemplate release;
  std::vector<std::pair<std::string, std::string>> headers;
  double poll_s = 0.5;
  double request_timeout_s = 5.0;
  RmfMqttOptions mqtt;  // instead of HTTP: Open-RMF's LiftRequest and LiftState over MQTT
  bool configured() const { return !call.url.empty() || !mqtt.broker.empty(); }
};

// A floor of the building and its map (a map_server YAML file; the map library names it by the file's stem).
struct FloorOptions {
  std::string name;
  std::filesystem::path map;
};

// The building the robot works in: floors with their maps, the lifts between them and its lift controller. With
// floors, the robot's maps are the floors' (map.file is not used) and the simulator's world is the floors side by
// side (sim.world is not used), its lifts moving the robot between them.
struct BuildingOptions {
  std::string name;
  std::vector<FloorOptions> floors;
  std::vector<nav::Lift> lifts;
  LiftControllerOptions controller;  // the ride's rules (timeouts, speeds) are in mission.lifts
  double sim_travel_s = 4.0;         // the simulated car: seconds per floor travelled
  double sim_floor_gap_m = 10.0;     // the simulated floors stand this far apart side by side
};

// The floors' names and maps (by their files' stems), and the lifts, as the mission runner takes them.
nav::Building BuildingOf(const BuildingOptions& building);

struct Config;
// The map the simulator's world is drawn in (its dock, doors and start are in that map's frame): with a building, the
// first floor's; else the configured map (map.file, a map of the simulated world, as a robot's SLAM made it), else the
// world's own.
std::string SimMapName(const Config& config);

// devices.*: the driver serving each of the robot's devices (docs/hardware.md): the simulator's robot (sim), a ROS 2
// driver over DDS (dds, drivers/dds/devices.h), a native driver (create2, kobuki, turtlebot3, serial-text; rplidar,
// hokuyo, lds; realsense, openni2, stereo), or none (a robot without a laser,
// or without a camera: the laser's lanes are then its sight; not both). The simulator's robot is all of the devices or
// none: a simulated base carries the simulated camera and the simulated laser (either may be none); the other drivers
// mix freely.
enum class DeviceDriver {
  kSim,
  kDds,
  kNone,
  kCreate2,
  kKobuki,
  kTurtlebot3,
  kSerialText,  // bases
  kRplidar,
  kHokuyo,
  kLds,  // lasers
  kRealsense,
  kOpenni2,
  kStereo,     // cameras
  kDynamixel,  // the camera's pan servo
};
const char* ToString(DeviceDriver driver);

struct BaseSlotOptions {
  DeviceDriver driver = DeviceDriver::kSim;
  drivers::dds::DdsBaseOptions dds;
  drivers::create2::Create2Options create2;
  drivers::kobuki::KobukiOptions kobuki;
  drivers::turtlebot3::TurtleBot3Options turtlebot3;
  drivers::serial_text::SerialTextOptions serial_text;
};

struct LaserSlotOptions {
  DeviceDriver driver = DeviceDriver::kSim;
  drivers::dds::DdsLaserOptions dds;
  drivers::rplidar::RplidarOptions rplidar;
  drivers::hokuyo::HokuyoOptions hokuyo;
  drivers::lds::LdsOptions lds;
};

struct CameraSlotOptions {
  DeviceDriver driver = DeviceDriver::kSim;
  drivers::dds::DdsCameraOptions dds;
  double info_wait_s = 10.0;  // dds: how long corridord waits at start for the camera's CameraInfo
  drivers::realsense::RealSenseOptions realsense;
  drivers::openni2::OpenNi2Options openni2;
  drivers::stereo::StereoCameraOptions stereo;
  // The camera on a pan servo (devices.camera.pan): none (fixed on the robot), sim (sim.camera.pan), dynamixel.
  DeviceDriver pan_driver = DeviceDriver::kNone;
  drivers::dynamixel::PanServoOptions pan;
};

// gaze: the camera's gaze when it is on a pan servo (nav/policy/gaze.h; its pan range is the servo's).
struct CameraGazeOptions {
  bool enabled = true;  // false: the camera is held straight ahead
  double rate_hz = 10.0;
  nav::GazeOptions policy;
};

struct DevicesOptions {
  BaseSlotOptions base;
  LaserSlotOptions laser;
  CameraSlotOptions camera;
};

// ROS 2 over DDS (server/dds, drivers/dds): the robot's topics for ROS 2 tools, and what they may send.
struct DdsOptions {
  bool enabled = false;
  int domain_id = -1;                   // -1: the environment's ROS_DOMAIN_ID, else 0
  std::vector<std::string> peers;       // unicast discovery peers (IPv4); none: multicast discovery
  std::vector<std::string> interfaces;  // the only interfaces used (names or IPv4 addresses); none: all
  bool allow_writes = false;            // take /cmd_vel, /goal_pose and /initialpose (from any peer let in)
  // A DDS Security enclave (drivers/dds/participant.h); empty: no security, any peer on the network is let in.
  std::filesystem::path security_enclave;
  double camera_hz = 0.0;                  // depth image and camera info rate; 0: not published
  std::string cmd_vel_topic = "/cmd_vel";  // what ROS 2 tools drive the robot with (allow_writes)
};

// The domain DDS joins: dds.domain_id, else ROS_DOMAIN_ID, else 0. Throws ConfigError for a ROS_DOMAIN_ID that is
// not a number within 0..232.
int DdsDomain(const DdsOptions& dds);

struct LogOptions {
  std::string level = "info";  // trace, debug, info, warn, error
};

// The depth path's ground test: MORP (nav/ground/morp.h) or ASNS's AFDS (nav/ground/afds.h), giving the same lanes.
enum class GroundTest { kMorp, kAfds };

// ground: the test, the lanes and MORP's settings (nav::MorpOptions, its fields the keys), and AFDS's under afds
// (its step and drop heights are the lanes' max_step_m and max_drop_m).
struct GroundOptions {
  GroundTest test = GroundTest::kMorp;
  nav::MorpOptions morp;
  nav::AfdsOptions afds;
};

struct Config {
  ServerOptions server;
  StoreOptions store;
  MapOptions map;
  SafetyOptions safety;
  DevicesOptions devices;
  SimulatorOptions sim;
  GroundOptions ground;
  CameraGazeOptions gaze;            // where a camera on a pan servo looks (ASNS's IGM)
  nav::MultiViewOptions multi_view;  // a stereo camera's frames filtered over posed frames (MMSVF's step 5)
  nav::CostmapOptions planner;
  nav::MissionRunnerOptions mission;  // its docking options come from the docking section
  nav::ChargingOptions charging;      // docking.charge_below_percent, docking.retry_s
  TrackingOptions tracking;
  LocalizationOptions localization;
  OctreeOptions octomap;
  PerceptionOptions perception;
  FaceOptions face;
  WebhookOptions webhooks;
  FleetOptions fleet;
  DoorsOptions doors;  // the passing rules (request_m, hold_m, ...) are in mission.doors
  BuildingOptions building;
  DdsOptions dds;
  auth::AuthOptions auth;
  LogOptions log;
  std::filesystem::path file;  // where it was read from (absolute); empty when built in code
};

// The simulator drives the robot (devices.base.driver is sim).
inline bool Simulated(const Config& config) { return config.devices.base.driver == DeviceDriver::kSim; }

// Values given on the command line; each replaces its key before validation, so the same checks apply.
struct ConfigOverrides {
  std::optional<int> port;
  std::optional<std::filesystem::path> state_dir;
  std::optional<std::filesystem::path> map;
  std::optional<std::filesystem::path> world;
  std::optional<std::string> mqtt;  // fleet.vda5050.broker
};

// Sets the options one module takes from another's: MORP-RB, the obstacle memory, evasion and the comparison policy
// brake by the command gate's model, from the robot's front, at the mission's top speed. LoadConfig applies it; a
// program that fills a Config itself (the scenario runner) applies it after.
void ApplyDerivedOptions(Config& config);

// Loads and validates `file`. Relative paths in it are resolved against the file's folder; override paths against
// the working directory. Throws ConfigError with the key path for any problem.
Config LoadConfig(const std::filesystem::path& file, const ConfigOverrides& overrides = {});
// The YAML document in `file`; throws ConfigError naming the file when it cannot be read or parsed.
YAML::Node ReadConfigYaml(const std::filesystem::path& file);
// The configuration in `root`, checked as LoadConfig checks a file; relative paths resolve against `file`'s
// directory and errors name `file`. Every key read is recorded in `schema` when given. Throws ConfigError.
Config ConfigFromYaml(const YAML::Node& root, const std::filesystem::path& file, ConfigSchema* schema = nullptr);

}  // namespace corridor::server
