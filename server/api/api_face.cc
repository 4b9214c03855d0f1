#include "server/api/api_face.h"

#include <cctype>
#include <cmath>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

constexpr double kMaxHoldS = 600.0;
constexpr std::size_t kMaxSayChars = 200;

std::string ExpressionNames() {
  std::string names;
  for (int i = 0; i < face::kExpressionCount; ++i) {
    names += (i > 0 ? ", " : "") + std::string(face::ToString(static_cast<face::Expression>(i)));
  }
  return names;
}

// The request's command; throws ApiError 400 naming what is wrong.
FaceCommand ParseFaceCommand(const json& body) {
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
  AllowOnlyKeys(body, {"expression", "hold_s", "say"}, "");
  FaceCommand command;
  if (body.contains("expression")) {
    const json& e = body["expression"];
    const auto expression = e.is_string() ? face::ExpressionFromString(e.get<std::string>()) : std::nullopt;
    if (!expression) {
      throw ApiError(http::status::bad_request, "Invalid request", "expression: one of " + ExpressionNames());
    }
    command.expression = expression;
  }
  if (body.contains("hold_s")) {
    command.hold_s = RequireNumber(body, "hold_s", "");
    if (!(command.hold_s >= 0.0 && command.hold_s <= kMaxHoldS)) {
      throw ApiError(http::status::bad_request, "Invalid request", "hold_s: seconds from 0 to 600");
    }
  }
  if (body.contains("say")) {
    const json& say = body["say"];
    if (!say.is_string() || say.get<std::string>().empty() || say.get<std::string>().size() > kMaxSayChars ||
        say.get<std::string>().find_first_not_of(" \t\r\n") == std::string::npos) {
      throw ApiError(http::status::bad_request, "Invalid request", "say: a phrase of 1 to 200 characters");
    }
    command.say = say.get<std::string>();
  }
  if (!command.expression && command.say.empty()) {
    throw ApiError(http::status::bad_request, "Invalid request", "give an expression, a phrase to say, or both");
  }
  return command;
}

constexpr std::size_t kMaxPushed = 100;

bool ValidSourceName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (const char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') return false;
  }
  return true;
}

double FiniteNumber(const json& body, const char* key, const std::string& where) {
  return RequireNumber(body, key, where);
}

face::Detection ParseDetection(const json& j, const std::string& where, const std::string& source) {
  if (!j.is_object()) throw ApiError(http::status::bad_request, "Invalid request", where + ": expected an object");
  AllowOnlyKeys(j, {"class", "score", "box", "position"}, where);
  face::Detection d;
  d.source = source;
  if (!j.contains("class") || !j["class"].is_string() || j["class"].get<std::string>().empty() ||
      j["class"].get<std::string>().size() > 64) {
    throw ApiError(http::status::bad_request, "Invalid request", where + ".class: a name of 1 to 64 characters");
  }
  d.label = j["class"].get<std::string>();
  d.score = j.contains("score") ? FiniteNumber(j, "score", where) : 1.0;
  if (!(d.score >= 0.0 && d.score <= 1.0)) {
    throw ApiError(http::status::bad_request, "Invalid request", where + ".score: from 0 to 1");
  }
  if (j.contains("box")) {
    const json& b = j["box"];
    const std::string at = where + ".box";
    if (!b.is_object()) throw ApiError(http::status::bad_request, "Invalid request", at + ": expected {x, y, w, h}");
    AllowOnlyKeys(b, {"x", "y", "w", "h"}, at);
    const cv::Rect2d box(FiniteNumber(b, "x", at), FiniteNumber(b, "y", at), FiniteNumber(b, "w", at),
                         FiniteNumber(b, "h", at));
    if (!(box.width > 0.0 && box.height > 0.0)) {
      throw ApiError(http::status::bad_request, "Invalid request", at + ": w and h must be positive");
    }
    d.box = box;
  }
  if (j.contains("position")) {
    const json& p = j["position"];
    const std::string at = where + ".position";
    if (!p.is_object()) throw ApiError(http::status::bad_request, "Invalid request", at + ": expected {x, y, z}");
    AllowOnlyKeys(p, {"x", "y", "z"}, at);
    d.position = Eigen::Vector3d(FiniteNumber(p, "x", at), FiniteNumber(p, "y", at),
                                 p.contains("z") ? FiniteNumber(p, "z", at) : 0.0);
    if (d.position->head<2>().norm() > 100.0) {
      throw ApiError(http::status::bad_request, "Invalid request", at + ": within 100 m of the robot");
    }
  }
  return d;
}

}  // namespace

void FaceApi::AddDetectionRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/detections", Access::kViewer, Sync([this](const Request& r, const Params&) {
               const auto detections = bus_.Get(topics::kDetections).latest();
               return JsonResponse(r, ToJson(detections ? *detections : Detections{clock_.Now(), {}}));
             }));
  routes.Add(
      http::verb::post, "/api/v1/detections", Access::kOperator, Sync([this](const Request& r, const Params&) {
        if (perception_ == nullptr) {
          throw ApiError(http::status::conflict, "Perception is off", "perception.enabled is false", "perception_off");
        }
        const json body = ObjectBody(r, {"source", "ttl_s", "detections"});
        ExternalDetections pushed;
        if (!body.contains("source") || !body["source"].is_string() ||
            !ValidSourceName(body["source"].get<std::string>())) {
          throw ApiError(http::status::bad_request, "Invalid request",
                         "source: a name of letters, digits, '-', '_' and '.' (1 to 64)");
        }
        pushed.source = body["source"].get<std::string>();
        if (body.contains("ttl_s")) pushed.ttl_s = RequireNumber(body, "ttl_s", "");
        const double max_ttl = options_.max_ttl_s;
        if (!(pushed.ttl_s > 0.0 && pushed.ttl_s <= max_ttl)) {
          throw ApiError(http::status::bad_request, "Invalid request",
                         "ttl_s: seconds above 0, at most " + std::to_string(max_ttl));
        }
        if (!body.contains("detections") || !body["detections"].is_array() || body["detections"].size() > kMaxPushed) {
          throw ApiError(http::status::bad_request, "Invalid request", "detections: a list of at most 100");
        }
        for (std::size_t i = 0; i < body["detections"].size(); ++i) {
          pushed.items.push_back(
              ParseDetection(body["detections"][i], "detections[" + std::to_string(i) + "]", pushed.source));
        }
        pushed.received_ns = clock_.Now();
        const json accepted{{"source", pushed.source}, {"accepted", pushed.items.size()}, {"ttl_s", pushed.ttl_s}};
        perception_->Push(std::move(pushed));
        return JsonResponse(r, accepted, http::status::accepted);
      }));
}

FaceApi::FaceApi(Bus& bus, const drivers::Clock& clock, const PerceptionOptions& options, PerceptionNode* perception,
                 const SpokenPhrases& spoken)
    : bus_(bus), clock_(clock), options_(options), perception_(perception), spoken_(spoken) {}

void FaceApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/face", Access::kFace, Sync([this](const Request& r, const Params&) {
               const auto face = bus_.Get(topics::kFaceExpression).latest();
               return JsonResponse(r, ToJson(face ? *face : FaceState{}));
             }));
  routes.Add(http::verb::get, "/api/v1/face/speech/{sequence}", Access::kFace,
             Sync([this](const Request& r, const Params& p) {
               const std::string& text = p.at("sequence");
               const auto wav = spoken_.Find(ParseCount(text, "sequence: a phrase's said_sequence"));
               if (!wav) {
                 throw ApiError(http::status::not_found, "No such speech",
                                "phrase " + text + " was not said aloud (the voice is muted) or is no longer kept",
                                "no_speech");
               }
               return MakeResponse(r, http::status::ok, "audio/wav", *wav);
             }));
  routes.Add(http::verb::post, "/api/v1/face", Access::kOperator, Sync([this](const Request& r, const Params&) {
               const FaceCommand command = ParseFaceCommand(ParseJsonBody(r));
               bus_.Get(topics::kFaceCommand).Publish(command);
               json accepted{{"expression", command.expression ? json(std::string(face::ToString(*command.expression)))
                                                               : json(nullptr)},
                             {"hold_s", command.hold_s},
                             {"say", command.say}};
               return JsonResponse(r, accepted, http::status::accepted);
             }));
  AddDetectionRoutes(routes);
}

}  // namespace corridor::server
