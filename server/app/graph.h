// The daemon's node graph, built in one place from the configuration and the devices: corridord, the scenario runner
// and the daemon-level tests all build this, so there is one wiring of the navigation. It holds the bus, the
// executors, the store and map library, the planner, every node in the order they come up, and the API (without its
// HTTP transport, which corridord adds).
//
// With Schedule::kThreads the graph runs in real time on the wall clock (corridord). With Schedule::kLockstep it runs
// on the simulator's clock: the owner calls Step(), which advances the simulator by one physics step and then runs
// everything that fell due, executors polled in a fixed order, on the caller's thread. A lockstep run is faster than
// real time and the same every time for the same configuration and seed.
#pragma once

#include <memory>
#include <string>

#include "drivers/dds/participant.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "drivers/sim/sim_robot.h"
#include "nav/map/occupancy_grid.h"
#include "server/api/api.h"
#include "server/api/webhooks.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/nodes/driver_bridge.h"
#include "server/nodes/face_node.h"
#include "server/nodes/mission_node.h"
#include "server/nodes/planner_service.h"
#include "server/nodes/sim_node.h"
#include "server/runtime/bus.h"
#include "server/runtime/executor.h"
#include "server/runtime/node.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

// What the graph drives. All must outlive the graph.
struct Devices {
  drivers::DepthCamera* camera = nullptr;  // null: no camera fitted (the laser's lanes then stand in, GroundNode)
  drivers::DiffDriveBase& base;
  drivers::Laser2D* laser = nullptr;      // null: no laser fitted
  drivers::sim::SimRobot* sim = nullptr;  // the simulator, when the devices are simulated (its faults, its truth)
  drivers::Battery* battery = nullptr;    // null: nothing reports the battery
  // The simulated building's floors side by side (its truth is shown in the map frame of the floor it is on); null:
  // one floor, the world's frame the map's.
  std::shared_ptr<const drivers::sim::Floors> sim_floors;
  // The DDS participant the devices served over DDS use, for the bridge to share; null: the graph makes its own when
  // dds.enabled.
  drivers::dds::Participant* dds = nullptr;
  // The devices present, for their health (GET /api/v1/devices) and, with links, the gate's stop when one goes down.
  std::vector<DeviceSlot> slots{};
  drivers::PanServo* pan = nullptr;  // the camera's pan servo; null: the camera is fixed on the robot
};

// The map to start in: the map library's first map.
struct NamedMap {
  std::string name;
  nav::OccupancyGrid grid;
};

class Graph {
 public:
  // Builds everything, nothing running yet. `config.store.state_dir` must exist and be writable. With kLockstep,
  // `devices.sim` is required: its clock is the graph's. Throws std::runtime_error (or ConfigError, StoreError) for a
  // configuration that cannot be built. `tls_fingerprint`: the server certificate's, shown to whoever sets the robot
  // up.
  Graph(const Config& config, Devices devices, NamedMap map, Schedule schedule, std::string tls_fingerprint = "");
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;
  ~Graph();

  // Activates the nodes and starts the executors (threads: their threads; lockstep: nothing runs until Step).
  void Start();
  // Deactivates the nodes in reverse order (the control node first: the robot stops first), stops the executors,
  // cleans up, and takes the graph's handlers off the drivers (which may outlive it). Idempotent.
  void Stop();
  // Lockstep: one physics step of the simulator, then every timer and handler that fell due.
  void Step();

  const Config& config() const { return config_; }
  const drivers::Clock& clock() const { return clock_; }
  Bus& bus() { return bus_; }
  Executors& executors() { return executors_; }
  const Lifecycle& lifecycle() const { return lifecycle_; }
  PlannerService& planner() { return planner_; }
  MapLibrary& maps() { return *maps_; }
  Store& store() { return store_; }
  auth::AccessControl& access() { return access_; }
  const Api& api() const { return *api_; }
  const RobotCore& core() const { return *core_; }

 private:
  // Nothing new of the drivers' reaches the bus after it (a driver's callback already under way may still finish).
  void DisconnectDrivers();

  Config config_;
  drivers::SteadyClock wall_clock_;
  const drivers::Clock& clock_;
  Devices devices_;
  Bus bus_;
  std::unique_ptr<drivers::dds::Participant> own_dds_;  // when dds.enabled and the devices brought none
  Executors executors_;
  Store store_;
  auth::AccessControl access_;
  PlannerService planner_;
  std::unique_ptr<MapLibrary> maps_;
  Lifecycle lifecycle_;
  SimNode* sim_node_ = nullptr;  // owned by lifecycle_
  MissionNode* missions_ = nullptr;
  OctreeNode* octree_ = nullptr;              // owned by lifecycle_; null when octomap.enabled is false
  PerceptionNode* perception_ = nullptr;      // owned by lifecycle_; null when perception.enabled is false
  LocalizationNode* localization_ = nullptr;  // owned by lifecycle_
  std::shared_ptr<SpokenPhrases> spoken_ = std::make_shared<SpokenPhrases>();  // the face's, for the API
  std::shared_ptr<EventLog> events_ = std::make_shared<EventLog>();            // the face node's, for webhooks and API
  std::unique_ptr<Webhooks> webhooks_;                                         // on the io executor
  std::unique_ptr<RobotCore> core_;                                            // over the nodes lifecycle_ owns
  std::unique_ptr<Api> api_;
  bool started_ = false;
  bool stopped_ = false;
};

}  // namespace corridor::server
