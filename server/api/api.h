// The REST API and the WebSocket stream's messages, independent of the transport (http_server.h carries them).
// Every route is described in openapi.json; errors are RFC 9457 problem details (application/problem+json),
// with a machine-readable "code" where a client may want to act on the kind of error.
#pragma once

#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "drivers/sim/sim_robot.h"
#include "server/api/webhooks.h"
#include "server/app/robot_core.h"
#include "server/auth/gate.h"
#include "server/config/config.h"
#include "server/fleet/rmf.h"
#include "server/nodes/face_node.h"
#include "server/nodes/localization_node.h"
#include "server/nodes/mission_node.h"
#include "server/nodes/octree_node.h"
#include "server/nodes/perception_node.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
using Reply = std::function<void(Response)>;
using Params = std::map<std::string, std::string, std::less<>>;

// A request the API refuses; becomes a problem+json response with this status (and `code`, when not empty).
class ApiError : public std::runtime_error {
 public:
  ApiError(http::status status, std::string title, const std::string& detail, std::string code = "")
      : std::runtime_error(detail), status_(status), title_(std::move(title)), code_(std::move(code)) {}
  http::status status() const { return status_; }
  const std::string& title() const { return title_; }
  const std::string& code() const { return code_; }
  // For 429 and 503: when to try again (the Retry-After header); 0: not said.
  int retry_after_s() const { return retry_after_s_; }
  ApiError& RetryAfter(int seconds) {
    retry_after_s_ = seconds;
    return *this;
  }

 private:
  http::status status_;
  std::string title_;
  std::string code_;
  int retry_after_s_ = 0;
};

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail, unsigned version,
                         bool keep_alive, const std::string& code = "");

// Where a request comes from. The API works out who sends it from its credentials (Api::Identify).
struct Caller {
  std::string address;   // the peer's IP address; "" in process
  bool local = false;    // on the robot itself (loopback): the face screen
  bool trusted = false;  // a tool driving the graph in process (the scenario runner): no credentials needed
};

// What the API works with; all must outlive the Api.
struct ApiContext {
  Bus& bus;
  const Lifecycle& lifecycle;
  MapLibrary& maps;
  Store& store;
  PlannerService& planner;
  const RobotCore& core;        // every command that moves the robot or sets its pose
  OctreeNode* octree;           // null when the 3D map is off (octomap.enabled: false)
  PerceptionNode* perception;   // null when perception.enabled is false
  const SpokenPhrases& spoken;  // the audio of what the face said lately
  Webhooks& webhooks;           // on the io executor, as the handlers are
  auth::AccessControl& access;  // users, sessions, tokens, the audit log, who may call what
  const Config& config;
  const drivers::Clock& clock;
  Executor& io;                                  // replies that are computed elsewhere come back here
  Executor& control;                             // for the simulator's stalled-control-loop fault
  drivers::sim::SimRobot* sim = nullptr;         // the simulated robot, for fault injection; null with real drivers
  std::string tls_fingerprint{};                 // the server certificate's SHA-256, shown at setup; "" without TLS
  std::string robot_name{};                      // in robot_state (Open-RMF) and webhook payloads
  const drivers::Laser2D* laser = nullptr;       // where the laser is mounted (GET /api/v1/laser/scan); null: no laser
  const drivers::DepthCamera* camera = nullptr;  // its intrinsics and mounting (the camera's calibration); null: none
};

class Api {
 public:
  explicit Api(ApiContext context);

  // Answers one HTTP request through `reply`, which is called exactly once, on the io executor. Never throws.
  // Refuses with 401 or 403 what the caller may not do (server/auth/gate.h); every write is recorded in the audit log.
  void Handle(const Request& request, const Caller& caller, Reply reply) const;
  // For tools that drive the graph in process: a trusted caller.
  void Handle(const Request& request, Reply reply) const { Handle(request, Caller{"", false, true}, std::move(reply)); }

  // Who sends `request`, from its bearer token or session cookie; nobody when it has neither (or a stale session).
  // Throws ApiError 401 for a token that is not valid.
  struct Identity {
    std::optional<auth::Principal> who;
    bool by_cookie = false;  // the credentials are a cookie the browser sends by itself (CSRF matters)
  };
  Identity Identify(const Request& request, const Caller& caller) const;
  // Who may open the stream at /api/v1/stream and what it pushes them unasked ("state" to whoever may read; nothing
  // to the robot's screen, which subscribes to the face). Throws ApiError 401/403 for a caller who may not, or a
  // browser page of another origin (any credentials).
  struct StreamAdmission {
    Identity who;
    std::vector<std::string> subscriptions;
  };
  StreamAdmission AdmitStream(const Request& request, const Caller& caller) const;
  // Throws ApiError 401/403 unless `identity` has `needed`, or 403 for a cookie-carrying write from another origin.
  void CheckAccess(const Request& request, const Caller& caller, const Identity& identity, auth::Access needed) const;

  // The route table as declared: each route's method, path pattern ("/api/v1/missions/{id}") and the access it needs.
  // tests/api_routes_test.cc checks it against openapi.json both ways.
  struct RouteInfo {
    http::verb method;
    std::string pattern;
    auth::Access access;
  };
  std::vector<RouteInfo> Routes() const;

  nlohmann::json Teleop(const nlohmann::json& body, const std::string& source) const;
  // The reply to one message from a WebSocket client of /api/v1/stream: an acknowledgement, or {"type": "error",
  // "status", "title", "detail"} for any message it cannot take. Never throws; `subscriptions` changes only on a
  // valid subscribe message.
  // `who` is the stream's caller: teleop needs an operator, and the robot's screen without login may subscribe only to
  // the face's topics.
  nlohmann::json StreamReply(const std::string& text, std::vector<std::string>& subscriptions,
                             const Identity& who) const;
  std::optional<std::string> TopicMessage(const std::string& topic) const;

 private:
  using Handler = std::function<void(const Request&, const Params&, Reply)>;
  // A handler that needs to know its caller (logging in, minting a token): where from, and who (as the gate found).
  using CallerHandler = std::function<Response(const Request&, const Params&, const Caller&, const Identity&)>;
  struct Route {
    http::verb method;
    std::vector<std::string> segments;  // "{name}" captures a segment
    auth::Access access;                // who may call it (server/auth/gate.h)
    Handler handler;                    // one of the two
    CallerHandler caller_handler;
  };
  // The route `method` `segments` name (params filled), or null; `path_matched` tells whether another method would.
  const Route* Find(http::verb method, const std::vector<std::string>& segments, Params& params,
                    bool& path_matched) const;
  // The access a request needs: its route's; the console's files are public, and an API path with no route needs a
  // viewer (so that nobody learns which paths exist without logging in).
  static auth::Access AccessFor(const Route* route, const std::string& path);
  // A handler that answers synchronously.
  static Handler Sync(std::function<Response(const Request&, const Params&)> f);
  void Add(http::verb method, const std::string& pattern, auth::Access access, Handler handler);
  void AddWithCaller(http::verb method, const std::string& pattern, auth::Access access, CallerHandler handler);
  // `reply`, which for a write to the API first records it in the audit log.
  Reply Audited(const Request& request, const Caller& caller, const Identity& identity, const std::string& path,
                Reply reply) const;
  static ApiError TooManyAttempts(int retry_after_s);
  // Runs `work` and replies with its response, or with the problem it throws, on the io executor.
  void Answer(const Request& request, Reply reply, const std::function<Response()>& work) const;

  // StreamReply's work; throws ApiError for a message it cannot take.
  nlohmann::json StreamMessage(const std::string& text, std::vector<std::string>& subscriptions,
                               const Identity& who) const;
  void AddCoreRoutes();
  void AddNavigationRoutes();
  void AddMapRoutes();
  void AddLocalizationRoutes();
  void AddMappingRoutes();
  void AddSimLiftRoutes();
  void AddFaceRoutes();
  void AddDetectionRoutes();
  void AddWebhookRoutes();
  void AddAuthRoutes();
  void AddRmfRoutes();
  void AddCalibrationRoutes();
  // The Open-RMF robot state's inputs, from the bus now.
  RmfSample SampleForRmf() const;
  // {x, y, yaw} of `body`, on the active map (else 422 outside_map).
  nav::Pose2 ParsePoseOnMap(const nlohmann::json& body, const std::string& where) const;
  // 409 not_localizing unless localization maps and takes poses (RobotCore::NotLocalizing).
  void RequireLocalizing() const;

  Response ServeFile(const Request& request, const std::string& target) const;
  Response CameraImage(const Request& request, bool depth) const;
  void Plan(const Request& request, Reply reply) const;
  void StartMission(const Request& request, Reply reply) const;
  // Starts a mission through `goals` once each is somewhere the robot can stand (undocking goals are not checked: the
  // robot backs off where it stands); answers 201 with the mission, or 422 naming the first goal that is not.
  // `started`, when given, is told the new mission (before the reply) and makes the reply's body.
  void StartGoals(const Request& request, Reply reply, std::vector<nav::MissionGoal> goals, double speed_limit,
                  std::function<nlohmann::json(const MissionState&)> started = nullptr) const;
  void Dock(const Request& request, Reply reply) const;
  // The dock named `wanted` (name or id), or the nearest when empty; 422 when there is none.
  nav::Place FindDock(const std::string& wanted) const;
  // The goal that docks there (409 when docked already), and the goal that backs off the dock (409 when not docked).
  std::vector<nav::MissionGoal> DockGoals(const std::string& wanted) const;
  std::vector<nav::MissionGoal> UndockGoals() const;
  void Undock(const Request& request, Reply reply) const;
  // Pauses, resumes or cancels mission `id`.
  void MissionAction(const Request& request, Reply reply, const std::string& id, MissionStep step) const;
  nav::MissionGoal ParseGoal(const nlohmann::json& j, const std::string& where) const;

  ApiContext c_;
  drivers::TimeNs start_ns_;
  std::shared_ptr<std::atomic<bool>> control_stalled_ = std::make_shared<std::atomic<bool>>(false);
  std::vector<Route> routes_;
  std::shared_ptr<RmfCommands> rmf_commands_ = std::make_shared<RmfCommands>();
  std::shared_ptr<struct WheelCalibration>
      wheel_calibration_;  // a wheel calibration run under way (api_calibration.cc)
};

// The OpenAPI 3.1 document (server/api/openapi.json, built into the binary).
const std::string& OpenApiDocument();

// Helpers shared by the route files.
// JSON text of `value`; bytes that are not UTF-8 (a request's path, say) become U+FFFD instead of throwing.
std::string Dump(const nlohmann::json& value);
Response JsonResponse(const Request& request, const nlohmann::json& body, http::status status = http::status::ok);
Response MakeResponse(const Request& request, http::status status, std::string content_type, std::string body);
nlohmann::json ParseJsonBody(const Request& request);
// A required finite number; throws ApiError 400 naming `where` and `key`.
double RequireNumber(const nlohmann::json& body, const char* key, const std::string& where);
// A whole number >= 0 written in `text` (a path segment or query value); throws ApiError 400 with `what` it must be.
std::uint64_t ParseCount(const std::string& text, const std::string& what);
// One query parameter's value from "/path?a=1&b=2"; "true" for a bare key, "" when absent.
std::string QueryValue(std::string_view target, std::string_view key);
// The "after" query parameter of a log's page (events, audit): a sequence number, 0 when absent; 400 otherwise.
std::int64_t AfterParameter(std::string_view target);
// Throws ApiError 400 for a key not in `allowed`.
void AllowOnlyKeys(const nlohmann::json& body, std::initializer_list<const char*> allowed, const std::string& where);

}  // namespace corridor::server
