#include "server/app/graph.h"

#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstring>

#include "nav/demand.h"
#include "nav/mission/docking.h"
#include "nav/policy/evasion.h"
#include "server/app/simulator.h"
#include "server/dds/bridge.h"
#include "server/fleet/rmf_mqtt.h"
#include "server/nodes/charging_node.h"
#include "server/nodes/control_node.h"
#include "server/nodes/devices_node.h"
#include "server/nodes/door_node.h"
#include "server/nodes/driver_bridge.h"
#include "server/nodes/event_node.h"
#include "server/nodes/explore_node.h"
#include "server/nodes/face_node.h"
#include "server/nodes/floor_node.h"
#include "server/nodes/gaze_node.h"
#include "server/nodes/ground_node.h"
#include "server/nodes/lift_node.h"
#include "server/nodes/localization_node.h"
#include "server/nodes/multi_view_node.h"
#include "server/nodes/octree_node.h"
#include "server/nodes/perception_node.h"
#include "server/nodes/tracking_node.h"
#include "server/nodes/vda5050_node.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// The configuration as the graph runs it: evasion backs away only when a laser sees behind; without one, people are
// tracked in the forward camera's view.
Config Adjusted(Config config, const Devices& devices) {
  nav::EvasionOptions& evade = config.mission.navigator.evade;
  if (devices.laser == nullptr) evade = nav::ForForwardView(evade);
  if (devices.camera == nullptr) {
    if (devices.laser == nullptr) {
      throw ConfigError("devices: a robot needs a depth camera or a laser to see (camera and laser are both none)");
    }
    // The laser's lanes are the robot's sight; what reads depth images has none to read.
    config.safety.require_depth = false;
    config.octomap.enabled = false;
    config.perception.enabled = false;
    config.tracking.camera = false;
  }
  return config;
}

const drivers::Clock& ClockFor(Schedule schedule, const Devices& devices, const drivers::Clock& wall) {
  if (schedule == Schedule::kThreads) return wall;
  if (devices.sim == nullptr)
    throw std::runtime_error("a graph in lockstep needs the simulator: its clock is the graph's");
  return devices.sim->clock();
}

// The control executor's SCHED_FIFO priority: below the kernel's own threads (50), within corridor.service's
// LimitRTPRIO.
constexpr int kControlRtPriority = 10;

// The machine's name, as the robot's in webhook payloads.
std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0 || name[0] == '\0') return "corridor";
  return name;
}

// The simulator's dock as a place of the map the simulated building is drawn in, unless that map has a dock already.
void AddSimulatedDock(Store& store, const std::string& map, const nav::Pose2& pose) {
  const std::vector<nav::Place> places = store.Places(map);
  bool named_dock = false;
  for (const nav::Place& p : places) {
    if (p.kind == nav::PlaceKind::kDock) return;
    named_dock = named_dock || p.name == "dock";
  }
  store.PutPlace(map, nav::Place{NewId(), named_dock ? "simulated dock" : "dock", pose, nav::PlaceKind::kDock});
  spdlog::info("simulator: its dock is the place '{}' of map '{}'", named_dock ? "simulated dock" : "dock", map);
}

}  // namespace

Graph::Graph(const Config& config, Devices devices, NamedMap map, Schedule schedule, std::string tls_fingerprint)
    : config_(Adjusted(config, devices)),
      clock_(ClockFor(schedule, devices, wall_clock_)),
      devices_(devices),
      executors_(clock_, schedule),
      store_(config_.store.state_dir / "corridor.db"),
      access_(config_.store.state_dir / "accounts.db", config_.auth),
      planner_(executors_.planning, bus_, config_.planner) {
  // The tracker of moving objects, from the laser when there is one, else from the depth camera.
  std::unique_ptr<TrackingNode> tracking_node;
  if (config_.tracking.enabled && (devices_.laser != nullptr || config_.tracking.camera)) {
    TrackingSource source;
    if (devices_.laser != nullptr) source.base_T_laser = devices_.laser->base_T_laser();
    if (devices_.camera != nullptr) source.camera = devices_.camera->info().camera;
    tracking_node = std::make_unique<TrackingNode>(executors_.mapping, bus_, source, config_.tracking.objects,
                                                   config_.tracking.traffic);
  }
  std::optional<nav::Pose2> base_T_laser;
  if (devices_.laser != nullptr) base_T_laser = devices_.laser->base_T_laser();
  // The robot starts where it was last localized, when that was in the map it starts in (LocalizationNode::SetMap).
  const std::filesystem::path pose_file = config_.store.state_dir / "pose.json";
  // A map just built is saved and becomes the map in use.
  const auto map_built = [this](const std::string& name, nav::OccupancyGrid grid) {
    maps_->Add(name, std::move(grid));
  };
  // Where it was, when that was in the map it starts in: the first pose published (LocalizationNode::SetMap then
  // starts the filter there).
  std::optional<SavedPose> saved = LoadSavedPose(pose_file);
  // Without a camera there is a laser (CheckDevices), and localization reads the laser alone.
  const nav::PinholeCamera camera = devices_.camera != nullptr ? devices_.camera->info().camera : nav::PinholeCamera{};
  const nav::Pose2 start = saved && saved->place == map.name ? saved->pose : config_.sim.robot.start;
  auto localization_node =
      std::make_unique<LocalizationNode>(executors_.mapping, bus_, config_.localization, start, base_T_laser, camera,
                                         pose_file, std::move(saved), map_built);
  localization_ = localization_node.get();
  // The 3D map, from the depth camera at the estimated poses; its layer goes to the planner.
  std::unique_ptr<OctreeNode> octree_node;
  if (config_.octomap.enabled && devices_.camera != nullptr) {
    octree_node = std::make_unique<OctreeNode>(executors_.mapping3d, bus_, config_.octomap, camera,
                                               config_.localization.source != LocalizationOptions::Source::kMonteCarlo,
                                               config_.store.state_dir / "maps");
  }
  octree_ = octree_node.get();
  // Each map the library makes the one in use goes to every node that works on it, with its zones and doors.
  const auto use_map = [this](const std::shared_ptr<const ActiveMap>& active) {
    bus_.Get(topics::kMapInUse).Publish(MapInUseOf(active, config_, store_));
  };
  maps_ = std::make_unique<MapLibrary>(config_.store.state_dir, std::move(map.name), std::move(map.grid), use_map);
  // A building's floors: each floor's map, for missions that ride lifts between them.
  for (const FloorOptions& f : config_.building.floors) maps_->AddConfigured(f.map.stem().string(), f.map);
  {
    const auto active = maps_->active();
    use_map(active);
    spdlog::info("map '{}': {} x {} cells at {} m", active->name, active->grid.width(), active->grid.height(),
                 active->grid.resolution_m());
  }
  const bool multi_view = config_.multi_view.enabled && devices_.camera != nullptr;
  ConnectDrivers(bus_, clock_, devices_.camera, devices_.base, devices_.laser, devices_.battery, devices_.slots,
                 multi_view, devices_.pan);

  // The simulator's dock is a place on the map it stands in (as an installer would add a real one). A dock no mission
  // can reach (its staging pose against a wall) is a configuration error: it is refused here, before anything runs.
  if (devices_.sim != nullptr && devices_.sim->dock() && maps_->active()->name == SimMapName(config_)) {
    const nav::Pose2 dock = devices_.sim->dock()->options().pose;
    const nav::Costmap costmap(maps_->active()->grid, store_.Zones(maps_->active()->name), config_.planner);
    if (const auto why = nav::DockUnreachable(costmap, dock, config_.mission.docking.dock)) {
      throw ConfigError("sim.dock: no mission can dock there on map '" + maps_->active()->name + "': " + *why +
                        " (move the dock, or shorten docking.staging_distance_m)");
    }
    AddSimulatedDock(store_, maps_->active()->name, dock);
  }
  auto mission_node = std::make_unique<MissionNode>(executors_.control, bus_, planner_, config_.mission);
  missions_ = mission_node.get();
  core_ = std::make_unique<RobotCore>(config_, bus_, clock_, lifecycle_, planner_, *missions_, *localization_, *maps_,
                                      store_);
  // Brought up in this order and down in reverse: control goes first at shutdown, so the robot stops first.
  if (devices_.sim != nullptr) {
    auto sim_node = std::make_unique<SimNode>(executors_.sim, bus_, *devices_.sim, SimPoseFile(config_),
                                              SimWorldName(config_), devices_.sim_floors);
    sim_node_ = sim_node.get();
    lifecycle_.Add(std::move(sim_node));
  }
  const bool sim_truth = config_.localization.source == LocalizationOptions::Source::kSimTruth;
  if (sim_truth && devices_.sim == nullptr) {
    throw std::runtime_error("localization.source: sim_truth needs the simulator");
  }
  lifecycle_.Add(std::move(localization_node));
  if (octree_node) lifecycle_.Add(std::move(octree_node));
  if (config_.perception.enabled && devices_.camera != nullptr) {
    auto perception_node = std::make_unique<PerceptionNode>(executors_.perception, bus_, config_.perception, camera,
                                                            devices_.sim != nullptr);
    perception_ = perception_node.get();
    lifecycle_.Add(std::move(perception_node));
  }
  face::SocialOptions social;
  social.near_m = config_.safety.person_near_m;
  std::shared_ptr<const face::Speech> speech;
  if (!config_.face.mute) speech = std::make_shared<const face::Speech>(config_.face.voice);
  lifecycle_.Add(
      std::make_unique<FaceNode>(executors_.perception, bus_, config_.face, social, speech, spoken_, events_));
  WebhookOptions hooks = config_.webhooks;
  if (hooks.robot.empty()) hooks.robot = HostName();
  webhooks_ = std::make_unique<Webhooks>(executors_.io.context(), store_, clock_, hooks);
  lifecycle_.Add(std::make_unique<EventNode>(executors_.io, bus_, *events_, store_, *webhooks_));
  if (!config_.building.floors.empty()) {
    lifecycle_.Add(std::make_unique<FloorNode>(executors_.io, bus_, *maps_, config_.building));
  }
  if (multi_view) {
    lifecycle_.Add(std::make_unique<MultiViewNode>(executors_.control, bus_, camera, config_.multi_view));
  }
  if (devices_.pan != nullptr && devices_.camera != nullptr && config_.gaze.enabled) {
    nav::GazeOptions gaze = config_.gaze.policy;
    const drivers::PanLimits limits = devices_.pan->pan_limits();
    gaze.min_pan_rad = limits.min_rad;
    gaze.max_pan_rad = limits.max_rad;
    lifecycle_.Add(std::make_unique<GazeNode>(executors_.perception, bus_, config_.gaze.rate_hz, gaze));
  }
  if (devices_.camera != nullptr) {
    lifecycle_.Add(std::make_unique<GroundNode>(executors_.control, bus_, devices_.camera->info(), config_.ground,
                                                config_.mission.policy));
  } else {
    lifecycle_.Add(std::make_unique<GroundNode>(executors_.control, bus_, devices_.laser->base_T_laser(),
                                                devices_.laser->height_m(), config_.ground.morp));
  }
  if (tracking_node) lifecycle_.Add(std::move(tracking_node));
  auto explore_node = std::make_unique<ExploreNode>(executors_.mapping, bus_, *core_);
  lifecycle_.Add(std::move(mission_node));
  lifecycle_.Add(std::move(explore_node));
  lifecycle_.Add(std::make_unique<ChargingNode>(executors_.io, bus_, *core_, config_.charging));
  std::vector<drivers::DeviceLink*> links;
  for (const DeviceSlot& slot : devices_.slots) {
    if (slot.link != nullptr) links.push_back(slot.link);
  }
  lifecycle_.Add(std::make_unique<ControlNode>(executors_.control, bus_, devices_.base, config_.safety, links));
  lifecycle_.Add(std::make_unique<DevicesNode>(executors_.io, bus_, devices_.slots, config_.safety));
  // The building's door controller, when one is configured: missions ask it to open the doors on their way. In a
  // simulated world with doors that names none, the simulator's doors answer themselves.
  if (DoorsAnswer(config_)) {
    const DoorControllerOptions& o = config_.doors.controller;
    std::unique_ptr<DoorController> controller;
    if (!o.mqtt.broker.empty()) {
      controller = std::make_unique<RmfMqttDoorController>(o.mqtt);
    } else if (o.configured()) {
      controller = std::make_unique<HttpDoorController>(executors_.io.context(), o);
    } else if (devices_.sim != nullptr) {
      controller = std::make_unique<SimDoorController>(executors_.io.context(), *devices_.sim);
    }
    if (controller) lifecycle_.Add(std::make_unique<DoorNode>(executors_.io, bus_, std::move(controller), o.poll_s));
  }
  // The building's lift controller: missions to other floors call lifts through it. In a simulated building that
  // names none, the simulator's lifts answer themselves.
  const LiftControllerOptions& lifts = config_.building.controller;
  std::unique_ptr<LiftController> lift_controller;
  if (!lifts.mqtt.broker.empty()) {
    lift_controller = std::make_unique<RmfMqttLiftController>(lifts.mqtt);
  } else if (lifts.configured()) {
    lift_controller = std::make_unique<HttpLiftController>(executors_.io.context(), lifts);
  } else if (devices_.sim != nullptr && LiftsAnswer(config_)) {
    lift_controller = std::make_unique<SimLiftController>(executors_.io.context(), *devices_.sim);
  }
  if (lift_controller) {
    lifecycle_.Add(std::make_unique<LiftNode>(executors_.io, bus_, std::move(lift_controller), lifts.poll_s));
  }
  // A VDA 5050 master control's orders, when a broker is configured.
  if (!config_.fleet.vda5050.broker.empty()) {
    lifecycle_.Add(std::make_unique<Vda5050Node>(executors_.io, bus_, config_, *core_, hooks.robot));
  }
  lifecycle_.ConfigureAll();

  api_ = std::make_unique<Api>(ApiContext{bus_, *maps_, store_, planner_, *core_, octree_, perception_, *spoken_,
                                          *webhooks_, access_, config_, clock_, executors_.io, executors_.control,
                                          devices_.sim, std::move(tls_fingerprint), hooks.robot, devices_.laser,
                                          devices_.camera});

  // ROS 2 over DDS: last up, first down.
  if (config_.dds.enabled) {
    drivers::dds::Participant* participant = devices_.dds;
    if (participant == nullptr) {
      own_dds_ = MakeParticipant(config_.dds);
      participant = own_dds_.get();
    }
    RobotFrames frames;
    if (devices_.laser != nullptr) {
      Eigen::Isometry3d t = devices_.laser->base_T_laser().ToIsometry3();
      t.translation().z() = devices_.laser->height_m();
      frames.base_T_laser = t;
    }
    if (devices_.camera != nullptr) frames.camera = devices_.camera->info();
    for (const DeviceSlot& slot : devices_.slots) {
      if (slot.driver != "dds") continue;
      if (slot.device == nav::Device::kBase) frames.base_over_dds = true;
      if (slot.device == nav::Device::kLaser) frames.laser_over_dds = true;
      if (slot.device == nav::Device::kCamera) frames.camera_over_dds = true;
    }
    lifecycle_.Add(std::make_unique<DdsBridge>(executors_.dds, bus_, *participant, config_.dds, std::move(frames),
                                               *core_, *maps_, lifecycle_));
  }
}

Graph::~Graph() { Stop(); }

void Graph::DisconnectDrivers() {
  if (devices_.camera != nullptr) devices_.camera->SetFrameHandler({});
  devices_.base.SetOdometryHandler({});
  if (devices_.laser != nullptr) devices_.laser->SetScanHandler({});
  if (devices_.battery != nullptr) devices_.battery->SetBatteryHandler({});
  if (devices_.pan != nullptr) devices_.pan->SetReadingHandler({});
  for (const DeviceSlot& slot : devices_.slots) {
    if (slot.link != nullptr) slot.link->SetLinkHandler({});
  }
}

void Graph::Start() {
  if (started_) return;
  started_ = true;
  executors_.StartAll();
  if (executors_.schedule() == Schedule::kThreads) {
    // The control path at real-time priority where the service may have it (corridor.service grants LimitRTPRIO), so
    // that a board busy with mapping, perception and clients does not delay the robot's answer to a frame.
    executors_.control.Post([] {
      const sched_param param{.sched_priority = kControlRtPriority};
      if (const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); error != 0) {
        spdlog::info("control executor: normal priority (real-time priority {} refused: {})", kControlRtPriority,
                     std::strerror(error));
      } else {
        spdlog::info("control executor: real-time priority {} (SCHED_FIFO)", kControlRtPriority);
      }
    });
  }
  lifecycle_.ActivateAll();
}

void Graph::Stop() {
  if (!started_ || stopped_) return;
  stopped_ = true;
  lifecycle_.DeactivateAll();
  if (executors_.schedule() == Schedule::kLockstep) executors_.RunUntilIdle();
  executors_.StopAll();
  lifecycle_.CleanupAll();
  DisconnectDrivers();
}

void Graph::Step() {
  DEMAND(executors_.schedule() == Schedule::kLockstep && sim_node_ != nullptr && started_ && !stopped_);
  sim_node_->Step();
  executors_.RunUntilIdle();
}

}  // namespace corridor::server
