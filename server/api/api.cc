#include "server/api/api.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kVersion = "0.1.0";

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

Response JsonResponse(const Request& request, const json& body, http::status status = http::status::ok) {
  return MakeResponse(request, status, "application/json", body.dump());
}

[[noreturn]] void MethodNotAllowed(const Request& request) {
  throw ApiError(http::status::method_not_allowed, "Method not allowed",
                 std::string(request.method_string()) + " is not supported on " + std::string(request.target()));
}

json ParseJsonBody(const Request& request) {
  const auto content_type = request[http::field::content_type];
  if (!content_type.starts_with("application/json")) {
    throw ApiError(http::status::unsupported_media_type, "Unsupported media type",
                   "send the body as application/json");
  }
  json body = json::parse(request.body(), nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) throw ApiError(http::status::bad_request, "Malformed JSON", "the body is not valid JSON");
  return body;
}

double RequireNumber(const json& body, const char* key) {
  const auto it = body.find(key);
  if (it == body.end()) throw ApiError(http::status::bad_request, "Invalid command", std::string("missing '") + key + "'");
  if (!it->is_number()) {
    throw ApiError(http::status::bad_request, "Invalid command", std::string("'") + key + "' must be a number");
  }
  return it->get<double>();
}

std::string ContentTypeFor(const fs::path& file) {
  static const std::map<std::string, std::string> kTypes = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},   {".json", "application/json"},
      {".png", "image/png"},                 {".svg", "image/svg+xml"},
      {".map", "application/json"},          {".ico", "image/x-icon"}};
  const auto it = kTypes.find(file.extension().string());
  return it == kTypes.end() ? "application/octet-stream" : it->second;
}

// Splits "/path?a=1&b=2" into the path and one query parameter's value.
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

}  // namespace

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail, unsigned version,
                         bool keep_alive) {
  Response res{status, version};
  res.set(http::field::server, "corridord");
  res.set(http::field::content_type, "application/problem+json");
  res.keep_alive(keep_alive);
  res.body() = json{{"type", "about:blank"}, {"title", title}, {"status", static_cast<int>(status)}, {"detail", detail}}
                   .dump();
  res.prepare_payload();
  return res;
}

Api::Api(Bus& bus, const Lifecycle& lifecycle, const ActiveMap& map, const Config& config, const drivers::Clock& clock)
    : bus_(bus),
      lifecycle_(lifecycle),
      map_(map),
      config_(config),
      clock_(clock),
      start_ns_(clock.Now()),
      web_root_(config.server.web_root) {}

Response Api::Handle(const Request& request) const {
  try {
    return Route(request);
  } catch (const ApiError& e) {
    Response res = ProblemResponse(e.status(), e.title(), e.what(), request.version(), request.keep_alive());
    if (e.status() == http::status::method_not_allowed) res.set(http::field::allow, "GET, POST");
    return res;
  } catch (const std::exception& e) {
    spdlog::error("{} {}: {}", std::string(request.method_string()), std::string(request.target()), e.what());
    return ProblemResponse(http::status::internal_server_error, "Internal error", e.what(), request.version(), false);
  }
}

Response Api::Route(const Request& request) const {
  const std::string_view target = request.target();
  const std::string path(target.substr(0, target.find('?')));
  const bool get = request.method() == http::verb::get || request.method() == http::verb::head;
  const bool post = request.method() == http::verb::post;

  if (path == "/api/v1/health") {
    if (!get) MethodNotAllowed(request);
    return JsonResponse(request, {{"status", "ok"},
                                  {"version", kVersion},
                                  {"uptime_s", drivers::ToSeconds(clock_.Now() - start_ns_)}});
  }
  if (path == "/api/v1/state") {
    if (!get) MethodNotAllowed(request);
    return JsonResponse(request, State());
  }
  if (path == "/api/v1/map") {
    if (!get) MethodNotAllowed(request);
    const nav::OccupancyGrid& g = map_.grid;
    return JsonResponse(request, {{"name", map_.name},
                                  {"resolution_m", g.resolution_m()},
                                  {"width", g.width()},
                                  {"height", g.height()},
                                  {"origin", ToJson(g.origin())},
                                  {"image_url", "/api/v1/map/image"}});
  }
  if (path == "/api/v1/map/image") {
    if (!get) MethodNotAllowed(request);
    return MakeResponse(request, http::status::ok, "image/png", map_.png);
  }
  if (path == "/api/v1/teleop") {
    if (!post) MethodNotAllowed(request);
    return JsonResponse(request, Teleop(ParseJsonBody(request), "rest"));
  }
  if (path == "/api/v1/camera/depth" || path == "/api/v1/camera/color") {
    if (!get) MethodNotAllowed(request);
    return CameraImage(request, path == "/api/v1/camera/depth");
  }
  if (path == "/api/v1/topics") {
    if (!get) MethodNotAllowed(request);
    return JsonResponse(request, {{"topics", bus_.names()}});
  }
  if (path == "/api/v1/openapi.json") {
    if (!get) MethodNotAllowed(request);
    return MakeResponse(request, http::status::ok, "application/json", OpenApiDocument());
  }
  if (path.starts_with("/api/")) {
    throw ApiError(http::status::not_found, "Not found", "no API route " + path);
  }
  if (!get) MethodNotAllowed(request);
  return ServeFile(request, path);
}

json Api::State() const {
  json state;
  state["stamp_s"] = drivers::ToSeconds(clock_.Now() - start_ns_);
  const auto pose = bus_.Get(topics::kPose).latest();
  state["pose"] = pose ? ToJson(pose->pose) : json(nullptr);
  const auto odometry = bus_.Get(topics::kOdometry).latest();
  state["velocity"] = odometry ? ToJson(odometry->velocity) : ToJson(nav::Twist2{});
  state["bumper_pressed"] = odometry && odometry->bumper_pressed;
  const auto command = bus_.Get(topics::kCmdVel).latest();
  state["mode"] = command ? command->mode : "starting";
  state["stop_reason"] = command ? command->reason : "";
  state["command"] = command ? ToJson(command->twist) : ToJson(nav::Twist2{});
  const auto truth = bus_.Get(topics::kSimTruePose).latest();
  state["sim_true_pose"] = truth ? ToJson(truth->pose) : json(nullptr);
  const auto face = bus_.Get(topics::kFaceExpression).latest();
  state["face"] = face ? face->expression : "neutral";
  json nodes = json::array();
  for (const auto& node : lifecycle_.nodes()) nodes.push_back(node->Status());
  state["nodes"] = std::move(nodes);
  return state;
}

json Api::Teleop(const json& body, const std::string& source) const {
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid command", "expected a JSON object");
  for (const auto& [key, value] : body.items()) {
    if (key != "linear_mps" && key != "angular_rps" && key != "type") {
      throw ApiError(http::status::bad_request, "Invalid command", "unknown key '" + key + "'");
    }
  }
  const double v = RequireNumber(body, "linear_mps");
  const double w = RequireNumber(body, "angular_rps");
  if (!std::isfinite(v) || !std::isfinite(w)) {
    throw ApiError(http::status::bad_request, "Invalid command", "speeds must be finite numbers");
  }
  const SafetyOptions& s = config_.safety;
  const nav::Twist2 applied{std::clamp(v, -s.max_linear_mps, s.max_linear_mps),
                            std::clamp(w, -s.max_angular_rps, s.max_angular_rps)};
  bus_.Get(topics::kTeleop).Publish(TeleopCommand{{v, w}, clock_.Now(), source});
  return {{"applied", ToJson(applied)}, {"expires_in_s", s.teleop_deadman_s}};
}

std::optional<json> Api::TopicMessage(const std::string& topic) const {
  if (topic == "state") return json{{"topic", "state"}, {"data", State()}};
  const TopicBase* t = bus_.Find(topic);
  if (t == nullptr) return std::nullopt;
  auto data = t->LatestJson();
  if (!data) return std::nullopt;
  return json{{"topic", topic}, {"data", std::move(*data)}};
}

json Api::StreamMessage(const std::string& text, std::vector<std::string>& subscriptions) const {
  const json message = json::parse(text, nullptr, false);
  if (message.is_discarded() || !message.is_object()) {
    throw ApiError(http::status::bad_request, "Malformed message", "stream messages are JSON objects");
  }
  const std::string type = message.value("type", "");
  if (type == "teleop") return {{"type", "teleop_ack"}, {"data", Teleop(message, "websocket")}};
  if (type == "subscribe") {
    const auto topics = message.find("topics");
    if (topics == message.end() || !topics->is_array()) {
      throw ApiError(http::status::bad_request, "Malformed message", "'topics' must be a list of topic names");
    }
    std::vector<std::string> wanted;
    for (const json& t : *topics) {
      if (!t.is_string()) throw ApiError(http::status::bad_request, "Malformed message", "topic names are strings");
      const std::string name = t.get<std::string>();
      if (name != "state" && bus_.Find(name) == nullptr) {
        throw ApiError(http::status::not_found, "Unknown topic", "no topic '" + name + "'");
      }
      wanted.push_back(name);
    }
    subscriptions = std::move(wanted);
    return {{"type", "subscribed"}, {"topics", subscriptions}};
  }
  throw ApiError(http::status::bad_request, "Malformed message", "unknown message type '" + type + "'");
}

Response Api::CameraImage(const Request& request, bool depth) const {
  const auto frame = bus_.Get(topics::kRgbd).latest();
  if (!frame) throw ApiError(http::status::service_unavailable, "No camera frame", "the camera has not sent a frame yet");
  std::vector<std::uint8_t> bytes;
  std::string type = "image/png";
  if (!depth) {
    cv::imencode(".jpg", frame->color_bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, 85});
    type = "image/jpeg";
  } else if (QueryValue(request.target(), "colormap") == "true") {
    // For people: near is warm, far is cool, holes are black.
    cv::Mat scaled;
    const double max_mm = std::max(1.0, config_.sim.robot.camera.max_range_m * 1000.0);
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
  const std::string relative = target == "/" ? "index.html" : target.substr(1);
  if (relative.find("..") != std::string::npos || relative.find('\0') != std::string::npos) {
    throw ApiError(http::status::bad_request, "Bad path", "path must not contain '..'");
  }
  const fs::path file = web_root_ / relative;
  std::ifstream in(file, std::ios::binary);
  if (web_root_.empty() || !fs::is_regular_file(file) || !in) {
    throw ApiError(http::status::not_found, "Not found", "no file " + target);
  }
  std::ostringstream body;
  body << in.rdbuf();
  Response res = MakeResponse(request, http::status::ok, ContentTypeFor(file), body.str());
  if (request.method() == http::verb::head) res.body().clear();
  return res;
}

}  // namespace corridor::server
