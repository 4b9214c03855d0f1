// corridord: the robot's daemon. Loads the configuration, starts the drivers (or the simulator), the nodes and
// the HTTP/WebSocket server, and on SIGINT/SIGTERM stops the robot first, then everything else.
#include <signal.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <iostream>

#include "drivers/sim/sim_robot.h"
#include "nav/map/map_io.h"
#include "nav/policy/evasion.h"
#include "server/api/http_server.h"
#include "server/nodes/control_node.h"
#include "server/nodes/driver_bridge.h"
#include "server/nodes/face_node.h"
#include "server/nodes/ground_node.h"
#include "server/nodes/tracking_node.h"
#include "server/nodes/localization_node.h"
#include "server/nodes/mission_node.h"
#include "server/nodes/sim_node.h"
#include "server/runtime/config.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage = R"(usage: corridord [options]

The corridor robot daemon: navigation stack, drivers (or the built-in simulator), and the
browser console and REST/WebSocket API on one HTTP port.

options:
  --config FILE      configuration file (default: config/corridor.yaml in the source tree,
                     or /etc/corridor/corridor.yaml when installed)
  --port N           HTTP port, 0 for any free port (server.port)
  --state-dir DIR    where maps, the database and the last pose are kept (store.state_dir)
  --map FILE.yaml    a ROS map_server map to work in (map.file)
  --world FILE       the simulator's world: a map_server .yaml, an SDF .world, or a mesh (sim.world)
  --version          print the version and exit
  --help             print this help and exit
)";

struct CommandLine {
  fs::path config;
  ConfigOverrides overrides;
};

// Returns nullopt after printing help or version; throws std::invalid_argument for a bad command line.
std::optional<CommandLine> ParseCommandLine(int argc, char** argv) {
  CommandLine cl;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return std::nullopt;
    } else if (arg == "--version") {
      std::cout << "corridord " << CORRIDOR_VERSION << "\n";
      return std::nullopt;
    } else if (arg == "--config") {
      cl.config = value();
    } else if (arg == "--port") {
      const std::string text = value();
      int port = -1;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), port);
      if (ec != std::errc() || end != text.data() + text.size()) throw std::invalid_argument("--port needs a number");
      cl.overrides.port = port;
    } else if (arg == "--state-dir") {
      cl.overrides.state_dir = value();
    } else if (arg == "--map") {
      cl.overrides.map = value();
    } else if (arg == "--world") {
      cl.overrides.world = value();
    } else {
      throw std::invalid_argument("unknown option " + arg);
    }
  }
  if (cl.config.empty()) {
    cl.config = fs::exists("/etc/corridor/corridor.yaml") ? fs::path("/etc/corridor/corridor.yaml")
                                                           : fs::path(CORRIDOR_SOURCE_DIR) / "config/corridor.yaml";
  }
  return cl;
}

fs::path FindWebRoot(const fs::path& configured) {
  if (!configured.empty()) return configured;
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  for (const fs::path& candidate :
       {exe.parent_path().parent_path() / "share/corridor/web", fs::path(CORRIDOR_SOURCE_DIR) / "web/dist"}) {
    if (fs::exists(candidate / "index.html")) return candidate;
  }
  spdlog::warn("the console is not built (web/dist/index.html missing): run ./dev build; the API still works");
  return {};
}

void PrepareStateDir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path probe = dir / ".write-test";
  std::ofstream(probe) << "ok";
  if (ec || !fs::exists(probe)) throw std::runtime_error("store.state_dir: cannot write to " + dir.string());
  fs::remove(probe);
}

// The map to work in and its name: the configured map file, else the simulator's world when it is a map, else
// the world's collision slice (what the robot can bump into).
std::pair<std::string, nav::OccupancyGrid> InitialMap(const Config& config, const drivers::sim::World* world) {
  if (!config.map.file.empty()) return {config.map.file.stem().string(), nav::LoadMap(config.map.file)};
  if (world != nullptr && world->source_map) return {config.sim.world.stem().string(), *world->source_map};
  if (world != nullptr) return {config.sim.world.stem().string() + "-collision", world->collision};
  throw std::runtime_error("map.file: required when the simulator is disabled");
}

int Run(const CommandLine& cl) {
  const Config config = [&] {
    Config c = LoadConfig(cl.config, cl.overrides);
    c.server.web_root = FindWebRoot(c.server.web_root);
    // Evasion backs away only when a laser sees behind; without one, people are tracked in the forward camera's view.
    if (!c.sim.robot.laser.enabled) c.mission.evade = nav::ForForwardView(c.mission.evade);
    return c;
  }();
  spdlog::set_level(spdlog::level::from_str(config.log.level));
  spdlog::info("corridord {} with {}", CORRIDOR_VERSION, cl.config.string());
  PrepareStateDir(config.store.state_dir);
  if (!config.sim.enabled) {
    throw std::runtime_error("sim.enabled: false needs real drivers, and none is built yet; run with the simulator");
  }

  auto world = [&] {
    drivers::sim::World w = drivers::sim::LoadWorld(config.sim.world, config.sim.world_options);
    drivers::sim::AddObstacles(w, config.sim.obstacles);  // in the world, not in its map
    return std::make_shared<const drivers::sim::World>(std::move(w));
  }();
  auto [map_name, map_grid] = InitialMap(config, world.get());
  Store store(config.store.state_dir / "corridor.db");

  const nav::Pose2 start = config.sim.robot.start;
  drivers::sim::SimOptions sim_options = config.sim.robot;
  if (config.sim.pedestrians > 0) {
    std::mt19937 rng(config.sim.robot.seed);
    drivers::sim::RouteArea area;
    area.center = start.translation();
    area.within_m = config.sim.pedestrians_within_m;
    area.clearance_m = 1.5;
    sim_options.pedestrians =
        drivers::sim::RandomRoutes(world->collision, config.sim.pedestrians, sim_options.crowd.radius_m, area, rng);
    spdlog::info("simulator: {} pedestrian(s) walking near the start", sim_options.pedestrians.size());
  }
  drivers::sim::SimRobot robot(world, sim_options);
  {
    drivers::sim::DiffDriveSim probe(world->collision, config.sim.robot.base, start);
    if (probe.Collides(start)) {
      throw std::runtime_error("sim.start: the robot at (" + std::to_string(start.x_m) + ", " +
                               std::to_string(start.y_m) + ") overlaps an obstacle or is outside the world");
    }
  }

  // Signals are taken by the main thread only: block them before any other thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  const drivers::SteadyClock wall_clock;
  Bus bus;
  Executors executors;
  PlannerService planner(executors.planning, config.planner);
  // The tracker of moving objects, from the laser when there is one, else from the depth camera: the map's walls are
  // not objects to track.
  std::unique_ptr<TrackingNode> tracking_node;
  if (config.tracking.enabled && (config.sim.robot.laser.enabled || config.tracking.camera)) {
    TrackingSource source;
    if (config.sim.robot.laser.enabled) source.base_T_laser = robot.base_T_laser();
    source.camera = robot.info().camera;
    tracking_node = std::make_unique<TrackingNode>(
        executors.mapping, bus, wall_clock, source, config.tracking.objects, config.tracking.traffic,
        [&planner](std::shared_ptr<const std::vector<float>> cost, const nav::OccupancyGrid* map) {
          planner.SetTraffic(std::move(cost), map);
        });
  }
  TrackingNode* const tracking = tracking_node.get();
  // Each active map goes to the planner and, for its walls, to the tracker.
  const auto use_map = [&planner, tracking](const std::shared_ptr<const ActiveMap>& map) {
    const std::shared_ptr<const nav::OccupancyGrid> grid(map, &map->grid);
    planner.SetMap(grid);
    if (tracking != nullptr) tracking->SetMap(grid);
  };
  MapLibrary maps(config.store.state_dir, map_name, std::move(map_grid), use_map);
  {
    const auto map = maps.active();
    use_map(map);
    planner.SetZones(store.Zones(map->name));
    spdlog::info("map '{}': {} x {} cells at {} m", map->name, map->grid.width(), map->grid.height(),
                 map->grid.resolution_m());
  }
  ConnectDrivers(bus, wall_clock, robot, robot, &robot);
  Lifecycle lifecycle;
  // Mission documents are written to the database on the io executor, off the control path.
  const auto persist = [&store, &executors](nlohmann::json doc) {
    executors.io.Post([&store, doc = std::move(doc)] {
      try {
        store.PutMission(doc["id"].get<std::string>(), doc);
      } catch (const StoreError& e) {
        spdlog::error("{}", e.what());
      }
    });
  };
  auto mission_node =
      std::make_unique<MissionNode>(executors.control, bus, wall_clock, planner, config.mission, persist);
  MissionNode& missions = *mission_node;
  // Brought up in this order and down in reverse: control goes first at shutdown, so the robot stops first.
  lifecycle.Add(std::make_unique<SimNode>(executors.sim, bus, robot, wall_clock));
  lifecycle.Add(std::make_unique<LocalizationNode>(executors.mapping, bus, wall_clock, start));
  lifecycle.Add(std::make_unique<FaceNode>(executors.perception, bus, wall_clock));
  lifecycle.Add(std::make_unique<GroundNode>(executors.control, bus, wall_clock, robot.info(), config.ground));
  if (tracking_node) lifecycle.Add(std::move(tracking_node));
  lifecycle.Add(std::move(mission_node));
  lifecycle.Add(std::make_unique<ControlNode>(executors.control, bus, robot, wall_clock, config.safety));
  lifecycle.ConfigureAll();

  const Api api({bus, lifecycle, maps, store, planner, missions, config, wall_clock, executors.io, &robot});
  HttpServer server(executors.io, api, config.server);
  server.Start();
  executors.StartAll();
  lifecycle.ActivateAll();
  spdlog::info("listening on http://{}:{}", config.server.bind_address, server.port());
  std::cerr << std::flush;

  int signal_number = 0;
  sigwait(&signals, &signal_number);
  spdlog::info("{}: stopping the robot, then shutting down", strsignal(signal_number));
  lifecycle.DeactivateAll();
  server.Stop();
  executors.StopAll();
  lifecycle.CleanupAll();
  spdlog::info("stopped");
  return 0;
}

}  // namespace
}  // namespace corridor::server

int main(int argc, char** argv) {
  using namespace corridor::server;
  spdlog::set_default_logger(spdlog::stderr_color_mt("corridord"));
  std::optional<CommandLine> cl;
  try {
    cl = ParseCommandLine(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "corridord: " << e.what() << "\n\n" << kUsage;
    return 2;
  }
  if (!cl) return 0;
  try {
    return Run(*cl);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
