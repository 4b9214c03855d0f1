// corridord: the robot's daemon. Loads the configuration, starts the drivers (or the simulator), the nodes and
// the HTTP/WebSocket server, and on SIGINT/SIGTERM stops the robot first, then everything else.
#include <signal.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <iostream>

#include "server/api/http_server.h"
#include "server/app/graph.h"
#include "server/app/robot_devices.h"
#include "server/app/service.h"
#include "server/app/simulator.h"
#include "server/config/config.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage = R"(usage: corridord [options]
       corridord token create --role ROLE --name NAME [--config FILE] [--state-dir DIR]

The corridor robot daemon: navigation stack, drivers (or the built-in simulator), and the
browser console and REST/WebSocket API on one HTTP port.

options:
  --config FILE      configuration file (default: config/corridor.yaml in the source tree,
                     or /etc/corridor/corridor.yaml when installed)
  --port N           HTTP port, 0 for any free port (server.port)
  --state-dir DIR    where maps, the database and the last pose are kept (store.state_dir)
  --map FILE.yaml    a ROS map_server map to work in (map.file)
  --world FILE       the simulator's world: a map_server .yaml, an SDF .world, or a mesh (sim.world)
  --mqtt URL         a VDA 5050 master control's MQTT broker, mqtt://host:port (fleet.vda5050.broker)
  --version          print the version and exit
  --help             print this help and exit

token create mints an API token offline (for scripts, or to recover when no admin can log in)
and prints it once; ROLE is viewer, operator or admin. Run it as the daemon's user or root.
)";

struct CommandLine {
  fs::path config;
  ConfigOverrides overrides;
  bool token_create = false;  // corridord token create
  std::string token_role;
  std::string token_name;
};

// Returns nullopt after printing help or version; throws std::invalid_argument for a bad command line.
std::optional<CommandLine> ParseCommandLine(int argc, char** argv) {
  CommandLine cl;
  int first = 1;
  if (argc >= 3 && std::string(argv[1]) == "token" && std::string(argv[2]) == "create") {
    cl.token_create = true;
    first = 3;
  } else if (argc >= 2 && std::string(argv[1]) == "token") {
    throw std::invalid_argument("token: the only command is 'token create'");
  }
  for (int i = first; i < argc; ++i) {
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
    } else if (arg == "--mqtt") {
      cl.overrides.mqtt = value();
    } else if (cl.token_create && arg == "--role") {
      cl.token_role = value();
    } else if (cl.token_create && arg == "--name") {
      cl.token_name = value();
    } else {
      throw std::invalid_argument("unknown option " + arg);
    }
  }
  if (cl.token_create && (cl.token_role.empty() || cl.token_name.empty())) {
    throw std::invalid_argument("token create needs --role and --name");
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

// The state directory holds the accounts and webhook secrets: only the daemon's user may enter it.
void PrepareStateDir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::permissions(dir, fs::perms::owner_all, ec);
  const fs::path probe = dir / ".write-test";
  std::ofstream(probe) << "ok";
  if (ec || !fs::exists(probe)) throw std::runtime_error("store.state_dir: cannot write to " + dir.string());
  fs::remove(probe);
}

// corridord token create: a token straight into the accounts database, owned (when run as root) by the state
// directory's owner, the daemon's user.
int CreateToken(const CommandLine& cl) {
  const auto role = auth::RoleFromString(cl.token_role);
  if (!role) throw std::invalid_argument("--role must be viewer, operator or admin");
  const fs::path state_dir =
      cl.overrides.state_dir ? *cl.overrides.state_dir : LoadConfig(cl.config, cl.overrides).store.state_dir;
  PrepareStateDir(state_dir);
  const fs::path file = state_dir / "accounts.db";
  auto [token, secret] = auth::Accounts(file).CreateToken(cl.token_name, *role, "command line");
  struct stat owner {};
  if (::stat(state_dir.c_str(), &owner) == 0) {
    for (const char* suffix : {"", "-wal", "-shm"}) {
      const fs::path f = file.string() + suffix;
      if (fs::exists(f) && ::chown(f.c_str(), owner.st_uid, owner.st_gid) != 0) {
        throw std::runtime_error("cannot give " + f.string() + " to the state directory's owner");
      }
    }
  }
  std::cerr << "token " << token.id << " (" << token.name << ", " << auth::ToString(token.role)
            << "); it is shown only now:\n";
  std::cout << secret << "\n";
  return 0;
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
  // Signals are taken by the main thread only: block them before any other thread starts (DDS starts its own).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  // The robot's devices: the simulator's, or the robot's own through their drivers (devices.*).
  drivers::SteadyClock device_clock;
  RobotDevices devices(config, device_clock);

  std::optional<TlsIdentity> tls;
  if (config.server.tls.enabled) {
    tls = LoadOrCreateTlsIdentity(config.server.tls, config.store.state_dir);
    spdlog::info("TLS certificate {}{}, SHA-256 fingerprint {}", tls->certificate.string(),
                 tls->generated ? " (self-signed, made now)" : "", tls->fingerprint);
  }
  const Simulator* sim = devices.simulator();
  Graph graph(config, devices.devices(), InitialMap(config, sim ? sim->world.get() : nullptr), Schedule::kThreads,
              tls ? tls->fingerprint : "");
  HttpServer server(graph.executors().io, graph.api(), config.server, tls);
  server.Start();
  graph.Start();
  ServiceNotifier service(graph.executors().control);
  // The setup code before the port: whoever waits for "listening" in the journal has the code by then.
  if (const auto code = graph.access().setup.code()) {
    spdlog::warn(
        "no users yet: create the first admin in the console with the setup code {} (also shown on the "
        "robot's screen)",
        *code);
  }
  spdlog::info("listening on {}://{}:{}", tls ? "https" : "http", config.server.bind_address, server.port());
  if (tls && config.server.tls.redirect_port != 0) {
    spdlog::info("plain HTTP on port {} redirects to HTTPS", config.server.tls.redirect_port);
  }
  service.Ready("listening on port " + std::to_string(server.port()));
  std::cerr << std::flush;

  int signal_number = 0;
  sigwait(&signals, &signal_number);
  spdlog::info("{}: stopping the robot, then shutting down", strsignal(signal_number));
  service.Stopping();
  graph.Stop();
  devices.Stop();  // no driver callback may reach the graph once it is gone
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
    return cl->token_create ? CreateToken(*cl) : Run(*cl);
  } catch (const std::invalid_argument& e) {
    std::cerr << "corridord: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
