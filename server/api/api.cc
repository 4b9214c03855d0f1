#include "server/api/api.h"

#include <boost/asio/post.hpp>
#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <thread>

#include "drivers/discovery.h"
#include "drivers/openni2/openni2_camera.h"
#include "drivers/realsense/v4l2_capture.h"
#include "server/config/config_file.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;
using auth::Access;
using nlohmann::json;

// The serial ports, video nodes and OpenNI2 devices of this machine, with the driver each suggests.
json Hardware() {
  json serial = json::array();
  for (const drivers::SerialPortInfo& p : drivers::ListSerialPorts()) {
    serial.push_back({{"path", p.path}, {"names", p.names}, {"usb_id", p.usb_id}, {"driver", p.driver}});
  }
  json video = json::array();
  for (const drivers::realsense::VideoNode& v : drivers::realsense::ListVideoNodes()) {
    json formats = json::array();
    bool depth = false;
    for (const std::uint32_t f : v.formats) {
      std::string code;
      for (int shift = 0; shift < 32; shift += 8) code.push_back(static_cast<char>((f >> shift) & 0xFF));
      while (!code.empty() && code.back() == ' ') code.pop_back();
      formats.push_back(code);
      depth = depth || f == drivers::realsense::kZ16;
    }
    const bool realsense = depth && v.card.find("RealSense") != std::string::npos;
    video.push_back(
        {{"path", v.path}, {"name", v.card}, {"formats", formats}, {"driver", realsense ? "realsense" : ""}});
  }
  json openni2 = json::array();
  try {
    for (const drivers::openni2::OpenNi2Device& d : drivers::openni2::ListOpenNi2Devices()) {
      openni2.push_back({{"uri", d.uri}, {"name", d.name}, {"vendor", d.vendor}});
    }
  } catch (const std::runtime_error& e) {
    spdlog::warn("devices: listing OpenNI2 devices: {}", e.what());
  }
  return {{"serial", serial}, {"video", video}, {"openni2", openni2}};
}

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

std::vector<std::string> Split(std::string_view path) {
  std::vector<std::string> out;
  while (!path.empty()) {
    if (path.front() == '/') {
      path.remove_prefix(1);
      continue;
    }
    const auto slash = path.find('/');
    out.emplace_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash);
  }
  return out;
}

}  // namespace

std::uint64_t ParseCount(const std::string& text, const std::string& what) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    throw ApiError(http::status::bad_request, "Invalid request", what);
  }
  return value;
}

// One query parameter's value from "/path?a=1&b=2"; "true" for a bare key, "" when absent.
std::string QueryValue(std::string_view target, std::string_view key) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return "";
  std::string_view query = target.substr(q + 1);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == key) return eq == std::string_view::npos ? "true" : std::string(pair.substr(eq + 1));
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return "";
}

std::int64_t AfterParameter(std::string_view target) {
  const std::string text = QueryValue(target, "after");
  const std::uint64_t after = text.empty() ? 0 : ParseCount(text, "after: a sequence number, 0 or more");
  return static_cast<std::int64_t>(std::min<std::uint64_t>(after, std::numeric_limits<std::int64_t>::max()));
}

std::string Dump(const json& value) { return value.dump(-1, ' ', false, json::error_handler_t::replace); }

Response MakeResponse(const Request& request, http::status status, std::string content_type, std::string body) {
  Response res{status, request.version()};
  res.set(http::field::server, "corridord");
  res.set(http::field::content_type, std::move(content_type));
  res.set(http::field::cache_control, "no-store");
  res.keep_alive(request.keep_alive());
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

Response JsonResponse(const Request& request, const json& body, http::status status) {
  return MakeResponse(request, status, "application/json", Dump(body));
}

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail, unsigned version,
                         bool keep_alive, const std::string& code) {
  Response res{status, version};
  res.set(http::field::server, "corridord");
  res.set(http::field::content_type, "application/problem+json");
  res.keep_alive(keep_alive);
  json body = {{"type", "about:blank"}, {"title", title}, {"status", static_cast<int>(status)}, {"detail", detail}};
  if (!code.empty()) body["code"] = code;
  res.body() = Dump(body);
  res.prepare_payload();
  return res;
}

json ParseJsonBody(const Request& request) {
  const auto content_type = request[http::field::content_type];
  if (!content_type.starts_with("application/json")) {
    throw ApiError(http::status::unsupported_media_type, "Unsupported media type", "send the body as application/json");
  }
  json body = json::parse(request.body(), nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) throw ApiError(http::status::bad_request, "Malformed JSON", "the body is not valid JSON");
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Malformed request", "expected a JSON object");
  return body;
}

double RequireNumber(const json& body, const char* key, const std::string& where) {
  const std::string name = where.empty() ? key : where + "." + key;
  const auto it = body.find(key);
  if (it == body.end()) throw ApiError(http::status::bad_request, "Invalid request", "missing '" + name + "'");
  if (!it->is_number() || !std::isfinite(it->get<double>())) {
    throw ApiError(http::status::bad_request, "Invalid request", "'" + name + "' must be a finite number");
  }
  return it->get<double>();
}

void AllowOnlyKeys(const json& body, std::initializer_list<const char*> allowed, const std::string& where) {
  for (const auto& [key, value] : body.items()) {
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
      throw ApiError(http::status::bad_request, "Invalid request",
                     "unknown key '" + (where.empty() ? key : where + "." + key) + "'");
    }
  }
}

Api::Api(ApiContext context) : c_(context), start_ns_(context.clock.Now()) {
  AddCoreRoutes();
  AddNavigationRoutes();
  AddLocalizationRoutes();
  AddMapRoutes();
  AddFaceRoutes();
  AddDetectionRoutes();
  AddWebhookRoutes();
  AddAuthRoutes();
  AddRmfRoutes();
  AddCalibrationRoutes();
}

Api::Handler Api::Sync(std::function<Response(const Request&, const Params&)> f) {
  return [f = std::move(f)](const Request& request, const Params& params, Reply reply) { reply(f(request, params)); };
}

void Api::Add(http::verb method, const std::string& pattern, Access access, Handler handler) {
  routes_.push_back({method, Split(pattern), access, std::move(handler), nullptr});
}

void Api::AddWithCaller(http::verb method, const std::string& pattern, Access access, CallerHandler handler) {
  routes_.push_back({method, Split(pattern), access, nullptr, std::move(handler)});
}

std::vector<Api::RouteInfo> Api::Routes() const {
  std::vector<RouteInfo> routes;
  for (const Route& route : routes_) {
    std::string pattern;
    for (const std::string& segment : route.segments) pattern += "/" + segment;
    routes.push_back({route.method, pattern, route.access});
  }
  return routes;
}

const Api::Route* Api::Find(http::verb method, const std::vector<std::string>& segments, Params& params,
                            bool& path_matched) const {
  path_matched = false;
  for (const Route& route : routes_) {
    if (route.segments.size() != segments.size()) continue;
    Params captured;
    bool match = true;
    for (std::size_t i = 0; i < segments.size() && match; ++i) {
      const std::string& want = route.segments[i];
      if (want.size() > 2 && want.front() == '{' && want.back() == '}') {
        captured[want.substr(1, want.size() - 2)] = segments[i];
      } else {
        match = want == segments[i];
      }
    }
    if (!match) continue;
    path_matched = true;
    if (route.method != method) continue;
    params = std::move(captured);
    return &route;
  }
  return nullptr;
}

Access Api::AccessFor(const Route* route, const std::string& path) {
  if (route != nullptr) return route->access;
  return path.starts_with("/api/") ? Access::kViewer : Access::kPublic;
}

void Api::Answer(const Request& request, Reply reply, const std::function<Response()>& work) const {
  Response response;
  try {
    response = work();
  } catch (const ApiError& e) {
    response = ProblemResponse(e.status(), e.title(), e.what(), request.version(), request.keep_alive(), e.code());
    if (e.status() == http::status::method_not_allowed) {
      response.set(http::field::allow, "GET, POST, PUT, PATCH, DELETE");
    }
    if (e.retry_after_s() > 0) response.set(http::field::retry_after, std::to_string(e.retry_after_s()));
  } catch (const std::exception& e) {
    spdlog::error("{} {}: {}", std::string(request.method_string()), std::string(request.target()), e.what());
    response =
        ProblemResponse(http::status::internal_server_error, "Internal error", e.what(), request.version(), false);
  }
  boost::asio::post(c_.io.context(), [reply = std::move(reply), response = std::move(response)]() mutable {
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
  const Route* route = Find(method, Split(path), params, path_matched);
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
    if (path.starts_with("/api/")) throw ApiError(http::status::not_found, "Not found", "no API route " + path);
    if (method != http::verb::get) {
      throw ApiError(http::status::method_not_allowed, "Method not allowed", "only GET is supported on " + path);
    }
    return ServeFile(request, path);
  });
}

void Api::AddCoreRoutes() {
  Add(http::verb::get, "/api/v1/health", Access::kPublic, Sync([this](const Request& r, const Params&) {
        return JsonResponse(r, {{"status", "ok"},
                                {"version", CORRIDOR_VERSION},
                                {"uptime_s", drivers::ToSeconds(c_.clock.Now() - start_ns_)}});
      }));
  Add(http::verb::get, "/api/v1/state", Access::kViewer, Sync([this](const Request& r, const Params&) {
        return MakeResponse(r, http::status::ok, "application/json", c_.core.State()->text);
      }));
  Add(http::verb::post, "/api/v1/teleop", Access::kOperator,
      Sync([this](const Request& r, const Params&) { return JsonResponse(r, Teleop(ParseJsonBody(r), "rest")); }));
  // Fault injection for the simulator: what the robot does when a device stops answering, or its own control loop
  // stalls (the systemd watchdog's test).
  Add(http::verb::put, "/api/v1/sim/faults", Access::kOperator, Sync([this](const Request& r, const Params&) {
        if (c_.sim == nullptr) throw ApiError(http::status::not_found, "No simulator", "faults are simulated only");
        const json body = ParseJsonBody(r);
        AllowOnlyKeys(body, {"camera_stopped", "control_stalled"}, "");
        for (const auto& [key, value] : body.items()) {
          if (!value.is_boolean()) {
            throw ApiError(http::status::bad_request, "Invalid faults", key + ": expected true or false");
          }
        }
        if (body.contains("camera_stopped")) c_.sim->SetCameraStopped(body["camera_stopped"].get<bool>());
        if (body.contains("control_stalled")) {
          const bool stall = body["control_stalled"].get<bool>();
          if (stall && !control_stalled_->exchange(true)) {
            spdlog::warn("fault injected: the control loop stalls (for at most a minute)");
            c_.control.Post([stalled = control_stalled_] {
              const auto end = std::chrono::steady_clock::now() + std::chrono::minutes(1);
              while (*stalled && std::chrono::steady_clock::now() < end) {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
              }
              *stalled = false;
            });
          }
          if (!stall) *control_stalled_ = false;
        }
        return JsonResponse(
            r, {{"camera_stopped", c_.sim->camera_stopped()}, {"control_stalled", control_stalled_->load()}});
      }));
  Add(http::verb::get, "/api/v1/camera/depth", Access::kViewer,
      Sync([this](const Request& r, const Params&) { return CameraImage(r, true); }));
  Add(http::verb::get, "/api/v1/camera/color", Access::kViewer,
      Sync([this](const Request& r, const Params&) { return CameraImage(r, false); }));
  Add(http::verb::get, "/api/v1/devices", Access::kViewer, Sync([this](const Request& r, const Params&) {
        const auto health = c_.bus.Get(topics::kDevices).latest();
        if (!health) {
          throw ApiError(http::status::service_unavailable, "Not yet", "the devices' health is not reported yet");
        }
        return JsonResponse(r, ToJson(*health));
      }));
  // What is plugged in, for setting a robot up: serial ports, video nodes, OpenNI2 devices (admin: it names devices'
  // paths and serial numbers).
  Add(http::verb::get, "/api/v1/devices/hardware", Access::kAdmin,
      Sync([](const Request& r, const Params&) { return JsonResponse(r, Hardware()); }));
  Add(http::verb::get, "/api/v1/laser/scan", Access::kViewer, Sync([this](const Request& r, const Params&) {
        if (c_.laser == nullptr) throw ApiError(http::status::not_found, "No laser", "this robot has no laser");
        const auto scan = c_.bus.Get(topics::kScan).latest();
        if (!scan) throw ApiError(http::status::service_unavailable, "No scan", "the laser has not sent a scan yet");
        json body = ToJson(*scan);
        body["frame"] = "laser";
        body["base_T_laser"] = ToJson(c_.laser->base_T_laser());
        body["height_m"] = c_.laser->height_m();
        return JsonResponse(r, body);
      }));
  Add(http::verb::get, "/api/v1/topics", Access::kViewer, Sync([this](const Request& r, const Params&) {
        return JsonResponse(r, {{"topics", c_.bus.names()}});
      }));
  Add(http::verb::get, "/api/v1/openapi.json", Access::kPublic, Sync([](const Request& r, const Params&) {
        return MakeResponse(r, http::status::ok, "application/json", OpenApiDocument());
      }));
  // The configuration file: read, and changed with a JSON merge patch checked as strictly as at start-up.
  const auto config_file = [this]() {
    if (c_.config.file.empty()) throw ApiError(http::status::not_found, "No configuration file", "built in code");
    return c_.config.file;
  };
  Add(http::verb::get, "/api/v1/config", Access::kAdmin, Sync([config_file](const Request& r, const Params&) {
        const auto file = config_file();
        try {
          return JsonResponse(r, {{"file", file.string()}, {"config", ConfigDocument(file)}});
        } catch (const ConfigError& e) {
          throw ApiError(http::status::service_unavailable, "Configuration unreadable", e.what());
        }
      }));
  Add(http::verb::patch, "/api/v1/config", Access::kAdmin, Sync([config_file](const Request& r, const Params&) {
        const auto file = config_file();
        const json patch = ParseJsonBody(r);
        ConfigChange change;
        try {
          change = PatchConfigFile(file, patch);
        } catch (const ConfigError& e) {
          throw ApiError(http::status::unprocessable_entity, "Invalid configuration", e.what(), "invalid_config");
        } catch (const std::runtime_error& e) {
          throw ApiError(http::status::conflict, "Configuration not written", e.what(), "not_writable");
        }
        spdlog::info("configuration changed through the API: {}", fmt::join(change.changed, ", "));
        return JsonResponse(r, {{"file", file.string()},
                                {"config", change.document},
                                {"changed", change.changed},
                                {"restart_required", !change.changed.empty()},
                                {"detail", change.changed.empty() ? "nothing changed"
                                                                  : "corridord reads its configuration at start: "
                                                                    "restart it (systemctl restart corridor)"}});
      }));
  Add(http::verb::get, "/api/v1/stream", Access::kFace, Sync([](const Request&, const Params&) -> Response {
        throw ApiError(http::status::upgrade_required, "Upgrade required", "/api/v1/stream is a WebSocket endpoint");
      }));
}

json Api::Teleop(const json& body, const std::string& source) const {
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid command", "expected a JSON object");
  AllowOnlyKeys(body, {"linear_mps", "angular_rps", "type"}, "");
  const double v = RequireNumber(body, "linear_mps", "");
  const double w = RequireNumber(body, "angular_rps", "");
  const nav::Twist2 applied = c_.core.Teleop({v, w}, source);
  return {{"applied", ToJson(applied)}, {"expires_in_s", c_.config.safety.teleop_deadman_s}};
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
    return {{"type", "teleop_ack"}, {"data", Teleop(message, "websocket")}};
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

Response Api::CameraImage(const Request& request, bool depth) const {
  if (c_.config.devices.camera.driver == DeviceDriver::kNone) {
    throw ApiError(http::status::not_found, "No camera", "this robot has no camera (devices.camera.driver: none)");
  }
  const auto frame = c_.bus.Get(topics::kRgbd).latest();
  if (!frame)
    throw ApiError(http::status::service_unavailable, "No camera frame", "the camera has not sent a frame yet");
  std::vector<std::uint8_t> bytes;
  std::string type = "image/png";
  if (!depth) {
    cv::imencode(".jpg", frame->color_bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, 85});
    type = "image/jpeg";
  } else if (QueryValue(request.target(), "colormap") == "true") {
    // For people: near is warm, far is cool, holes are black.
    cv::Mat scaled;
    const double max_mm = std::max(1.0, c_.config.sim.robot.camera.max_range_m * 1000.0);
    frame->depth_mm.convertTo(scaled, CV_8U, -255.0 / max_mm, 255.0);
    cv::Mat colored;
    cv::applyColorMap(scaled, colored, cv::COLORMAP_TURBO);
    colored.setTo(cv::Scalar(0, 0, 0), frame->depth_mm == 0);
    cv::imencode(".png", colored, bytes);
  } else {
    cv::imencode(".png", frame->depth_mm, bytes);  // 16-bit, millimetres, 0 = no measurement
  }
  Response res = MakeResponse(request, http::status::ok, type, std::string(bytes.begin(), bytes.end()));
  res.set("X-Frame-Sequence", std::to_string(frame->sequence));
  res.prepare_payload();
  return res;
}

Response Api::ServeFile(const Request& request, const std::string& target) const {
  // The console at /, the face kiosk page at /face, the admin page at /admin.
  const std::string relative = target == "/"        ? "index.html"
                               : target == "/face"  ? "face.html"
                               : target == "/admin" ? "admin.html"
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
