// The REST API and the WebSocket stream's messages, independent of the transport (http_server.h carries them). Every
// route is described in openapi.json; errors are RFC 9457 problem details (rest.h). Api is the gate every request
// passes (who sends it, whether they may, the audit log) in front of the route table, which each resource's handler
// class (api_*.h) fills with its own routes and holds only the collaborators it needs.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "drivers/sim/sim_robot.h"
#include "server/api/api_auth.h"
#include "server/api/api_calibration.h"
#include "server/api/api_face.h"
#include "server/api/api_localization.h"
#include "server/api/api_map.h"
#include "server/api/api_navigation.h"
#include "server/api/api_rmf.h"
#include "server/api/api_sim.h"
#include "server/api/api_system.h"
#include "server/api/api_webhooks.h"
#include "server/api/rest.h"
#include "server/api/router.h"
#include "server/api/webhooks.h"
#include "server/app/robot_core.h"
#include "server/auth/gate.h"
#include "server/config/config.h"
#include "server/nodes/face_node.h"
#include "server/nodes/octree_node.h"
#include "server/nodes/perception_node.h"
#include "server/nodes/planner_service.h"
#include "server/runtime/bus.h"
#include "server/runtime/executor.h"
#include "server/store/map_library.h"
#include "server/store/store.h"

namespace corridor::server {

// What the API works with; all must outlive the Api.
struct ApiContext {
  Bus& bus;
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

  // The route table as declared; tests/api_routes_test.cc checks it against openapi.json both ways.
  std::vector<Router::RouteInfo> Routes() const { return routes_.Routes(); }

  // The reply to one message from a WebSocket client of /api/v1/stream: an acknowledgement, or {"type": "error",
  // "status", "title", "detail"} for any message it cannot take. Never throws; `subscriptions` changes only on a
  // valid subscribe message. `who` is the stream's caller: teleop needs an operator, and the robot's screen without
  // login may subscribe only to the face's topics.
  nlohmann::json StreamReply(const std::string& text, std::vector<std::string>& subscriptions,
                             const Identity& who) const;
  // The message the stream pushes for `topic` now ({"topic", "data"}), or nullopt when it has none.
  std::optional<std::string> TopicMessage(const std::string& topic) const;

 private:
  // The access a request needs: its route's; the console's files are public, and an API path with no route needs a
  // viewer (so that nobody learns which paths exist without logging in).
  static auth::Access AccessFor(const Router::Route* route, const std::string& path);
  // `reply`, which for a write to the API first records it in the audit log.
  Reply Audited(const Request& request, const Caller& caller, const Identity& identity, const std::string& path,
                Reply reply) const;
  // Runs `work` and replies with its response, or with the problem it throws, on the io executor.
  void Answer(const Request& request, Reply reply, const std::function<Response()>& work) const;
  // StreamReply's work; throws ApiError for a message it cannot take.
  nlohmann::json StreamMessage(const std::string& text, std::vector<std::string>& subscriptions,
                               const Identity& who) const;
  Response ServeFile(const Request& request, const std::string& target) const;

  ApiContext c_;
  // The resources, each with its routes.
  SystemApi system_;
  SimulatorApi simulator_;
  MissionRequests missions_;
  NavigationApi navigation_;
  LocalizationApi localization_;
  MapApi map_;
  FaceApi face_;
  WebhooksApi webhooks_;
  AccountsApi accounts_;
  RmfApi rmf_;
  CalibrationApi calibration_;
  Router routes_;
};

}  // namespace corridor::server
