#include "server/api/api.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;
using auth::Access;
using nlohmann::json;

// The API's documentation: a page (web/api-docs.html), open to anyone as the document it renders is.
constexpr std::string_view kApiDocs = "/api/docs";

std::string ContentTypeFor(const fs::path& file) {
  static const std::map<std::string, std::string> kTypes = {{".html", "text/html; charset=utf-8"},
                                                            {".js", "text/javascript; charset=utf-8"},
                                                            {".css", "text/css; charset=utf-8"},
                                                            {".json", "application/json"},
                                                            {".png", "image/png"},
                                                            {".svg", "image/svg+xml"},
                                                            {".map", "application/json"},
                                                            {".ico", "image/x-icon"}};
  const auto it = kTypes.find(file.extension().string());
  return it == kTypes.end() ? "application/octet-stream" : it->second;
}

}  // namespace

Api::Api(ApiContext context)
    : c_(context),
      system_(c_.bus, c_.core, c_.config, c_.clock, c_.laser),
      simulator_(c_.sim, c_.core, c_.control),
      missions_(c_.bus, c_.core, c_.maps, c_.store, c_.config),
      navigation_(c_.bus, c_.core, c_.store, c_.planner, missions_),
      localization_(c_.bus, c_.core, c_.config.localization),
      map_(c_.bus, c_.core, c_.config, c_.maps, c_.store, c_.planner, c_.octree, c_.sim != nullptr, c_.io),
      face_(c_.bus, c_.clock, c_.config.perception, c_.perception, c_.spoken),
      webhooks_(c_.store, c_.webhooks, c_.config.webhooks),
      accounts_(c_.access, c_.config.server.tls.enabled, c_.tls_fingerprint),
      rmf_(c_.bus, c_.core, c_.maps, c_.store, c_.config.building, missions_, c_.robot_name),
      calibration_(c_.bus, c_.config, c_.laser, c_.camera) {
  system_.AddRoutes(routes_);
  navigation_.AddRoutes(routes_);
  localization_.AddRoutes(routes_);
  simulator_.AddRoutes(routes_);
  map_.AddRoutes(routes_);
  face_.AddRoutes(routes_);
  webhooks_.AddRoutes(routes_);
  accounts_.AddRoutes(routes_);
  rmf_.AddRoutes(routes_);
  calibration_.AddRoutes(routes_);
  routes_.Add(http::verb::get, "/api/v1/stream", Access::kFace, Sync([](const Request&, const Params&) -> Response {
                throw ApiError(http::status::upgrade_required, "Upgrade required",
                               "/api/v1/stream is a WebSocket endpoint");
              }));
}

Access Api::AccessFor(const Router::Route* route, const std::string& path) {
  if (route != nullptr) return route->access;
  return path.starts_with("/api/") && path != kApiDocs ? Access::kViewer : Access::kPublic;
}

void Api::Answer(const Request& request, Reply reply, const std::function<Response()>& work) const {
  boost::asio::post(c_.io.context(), [reply = std::move(reply), response = Respond(request, work)]() mutable {
    reply(std::move(response));
  });
}

void Api::Handle(const Request& request, const Caller& caller, Reply reply) const {
  const std::string_view target = request.target();
  if (!target.starts_with('/')) {
    // Only the origin form (RFC 9112, 3.2.1) names something here; "*", absolute URLs and "?x" do not.
    Answer(request, std::move(reply), [target]() -> Response {
      throw ApiError(http::status::bad_request, "Bad request target",
                     "the request target must be a path starting with '/', got '" + std::string(target) + "'");
    });
    return;
  }
  const std::string path(target.substr(0, target.find('?')));
  const http::verb method = request.method() == http::verb::head ? http::verb::get : request.method();
  Params params;
  bool path_matched = false;
  const Router::Route* route = routes_.Find(method, path, params, path_matched);
  Identity identity;
  try {
    identity = Identify(request, caller);
    CheckAccess(request, caller, identity, AccessFor(route, path));
  } catch (...) {
    const std::exception_ptr error = std::current_exception();
    Answer(request, Audited(request, caller, identity, path, std::move(reply)),
           [error]() -> Response { std::rethrow_exception(error); });
    return;
  }
  reply = Audited(request, caller, identity, path, std::move(reply));
  if (route != nullptr) {
    // A handler that throws before handing off answers with the problem; one that hands off replies itself.
    try {
      if (route->caller_handler) {
        Answer(request, reply, [&] { return route->caller_handler(request, params, caller, identity); });
        return;
      }
      route->handler(request, params, [this, reply](Response r) {
        boost::asio::post(c_.io.context(), [reply, r = std::move(r)]() mutable { reply(std::move(r)); });
      });
    } catch (...) {
      const std::exception_ptr error = std::current_exception();
      Answer(request, reply, [error]() -> Response { std::rethrow_exception(error); });
    }
    return;
  }
  Answer(request, std::move(reply), [&]() -> Response {
    if (path_matched) {
      throw ApiError(http::status::method_not_allowed, "Method not allowed",
                     std::string(request.method_string()) + " is not supported on " + path);
    }
    if (path.starts_with("/api/") && path != kApiDocs) {
      throw ApiError(http::status::not_found, "Not found", "no API route " + path);
    }
    if (method != http::verb::get) {
      throw ApiError(http::status::method_not_allowed, "Method not allowed", "only GET is supported on " + path);
    }
    return ServeFile(request, path);
  });
}

std::optional<std::string> Api::TopicMessage(const std::string& topic) const {
  if (topic == "state") return R"({"topic":"state","data":)" + c_.core.State()->text + "}";
  const TopicBase* t = c_.bus.Find(topic);
  if (t == nullptr) return std::nullopt;
  auto data = t->LatestJson();
  if (!data) return std::nullopt;
  return Dump(json{{"topic", topic}, {"data", std::move(*data)}});
}

json Api::StreamReply(const std::string& text, std::vector<std::string>& subscriptions, const Identity& who) const {
  const auto error = [](int status, const std::string& title, const std::string& detail) {
    return json{{"type", "error"}, {"status", status}, {"title", title}, {"detail", detail}};
  };
  try {
    return StreamMessage(text, subscriptions, who);
  } catch (const ApiError& e) {
    return error(static_cast<int>(e.status()), e.title(), e.what());
  } catch (const std::exception& e) {
    // A message the API did not foresee: this client gets an error, the others and the daemon go on.
    spdlog::error("stream message: {}", e.what());
    return error(500, "Internal error", e.what());
  }
}

json Api::StreamMessage(const std::string& text, std::vector<std::string>& subscriptions, const Identity& who) const {
  const json message = json::parse(text, nullptr, false);
  if (message.is_discarded() || !message.is_object()) {
    throw ApiError(http::status::bad_request, "Malformed message", "stream messages are JSON objects");
  }
  const auto type_field = message.find("type");
  if (type_field == message.end() || !type_field->is_string()) {
    throw ApiError(http::status::bad_request, "Malformed message", "'type' must be one of \"subscribe\", \"teleop\"");
  }
  const std::string type = type_field->get<std::string>();
  if (type == "teleop") {
    if (!who.who || who.who->role < auth::Role::kOperator) {
      throw ApiError(http::status::forbidden, "Forbidden", "driving needs the operator role");
    }
    return {{"type", "teleop_ack"}, {"data", system_.Teleop(message, "websocket")}};
  }
  if (type == "subscribe") {
    const auto topics = message.find("topics");
    if (topics == message.end() || !topics->is_array()) {
      throw ApiError(http::status::bad_request, "Malformed message", "'topics' must be a list of topic names");
    }
    std::vector<std::string> wanted;
    for (const json& t : *topics) {
      if (!t.is_string()) throw ApiError(http::status::bad_request, "Malformed message", "topic names are strings");
      const std::string name = t.get<std::string>();
      if (name != "state" && c_.bus.Find(name) == nullptr) {
        throw ApiError(http::status::not_found, "Unknown topic", "no topic '" + name + "'");
      }
      // The robot's screen, not logged in, sees the face and nothing else.
      if (!who.who && !c_.access.options.anonymous_viewer && !name.starts_with("face/")) {
        throw ApiError(http::status::unauthorized, "Unauthorized", "log in to subscribe to '" + name + "'");
      }
      wanted.push_back(name);
    }
    subscriptions = std::move(wanted);
    return {{"type", "subscribed"}, {"topics", subscriptions}};
  }
  throw ApiError(http::status::bad_request, "Malformed message", "unknown message type '" + type + "'");
}

Response Api::ServeFile(const Request& request, const std::string& target) const {
  // The console at /, the face kiosk page at /face, the admin page at /admin, the settings at /settings, the API's
  // documentation at /api/docs.
  const std::string relative = target == "/"           ? "index.html"
                               : target == "/face"     ? "face.html"
                               : target == "/admin"    ? "admin.html"
                               : target == "/settings" ? "settings.html"
                               : target == kApiDocs    ? "api-docs.html"
                                                       : target.substr(1);
  if (relative.find("..") != std::string::npos || relative.find('\0') != std::string::npos) {
    throw ApiError(http::status::bad_request, "Bad path", "path must not contain '..'");
  }
  const fs::path& root = c_.config.server.web_root;
  const fs::path file = root / relative;
  std::ifstream in(file, std::ios::binary);
  if (root.empty() || !fs::is_regular_file(file) || !in) {
    throw ApiError(http::status::not_found, "Not found", "no file " + target);
  }
  std::ostringstream body;
  body << in.rdbuf();
  Response res = MakeResponse(request, http::status::ok, ContentTypeFor(file), body.str());
  if (request.method() == http::verb::head) res.body().clear();
  return res;
}

}  // namespace corridor::server
