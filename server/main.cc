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

#include "server/api/http_server.h"
#include "server/app/graph.h"
#include "server/app/simulator.h"
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

int Run(const CommandLine& cl) {
  const Config config = [&] {
    Config c = LoadConfig(cl.config, cl.overrides);
    c.server.web_root = FindWebRoot(c.server.web_root);
    return c;
  }();
  spdlog::set_level(spdlog::level::from_str(config.log.level));
  spdlog::info("corridord {} with {}", CORRIDOR_VERSION, cl.config.string());
  PrepareStateDir(config.store.state_dir);
  if (!config.sim.enabled) {
    throw std::runtime_error("sim.enabled: false needs real drivers, and none is built yet; run with the simulator");
  }
  const Simulator sim = MakeSimulator(config);

  // Signals are taken by the main thread only: block them before any other thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  Graph graph(config, sim.devices(config), InitialMap(config, sim.world.get()), Schedule::kThreads);
  HttpServer server(graph.executors().io, graph.api(), config.server);
  server.Start();
  graph.Start();
  spdlog::info("listening on http://{}:{}", config.server.bind_address, server.port());
  std::cerr << std::flush;

  int signal_number = 0;
  sigwait(&signals, &signal_number);
  spdlog::info("{}: stopping the robot, then shutting down", strsignal(signal_number));
  graph.Stop();
  server.Stop();
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
