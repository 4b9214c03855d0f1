// Routes for the robot's face: GET /api/v1/face (the expression, and what it said last) and POST /api/v1/face (an
// app's or building system's request: an expression for a while, a phrase to say, or both).
#include <cmath>

#include "server/api/api.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

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

}  // namespace

void Api::AddFaceRoutes() {
  Add(http::verb::get, "/api/v1/face", Sync([this](const Request& r, const Params&) {
        const auto face = c_.bus.Get(topics::kFaceExpression).latest();
        return JsonResponse(r, ToJson(face ? *face : FaceState{}));
      }));
  Add(http::verb::post, "/api/v1/face", Sync([this](const Request& r, const Params&) {
        const FaceCommand command = ParseFaceCommand(ParseJsonBody(r));
        c_.bus.Get(topics::kFaceCommand).Publish(command);
        json accepted{{"expression", command.expression ? json(std::string(face::ToString(*command.expression)))
                                                          : json(nullptr)},
                      {"hold_s", command.hold_s},
                      {"say", command.say}};
        return JsonResponse(r, accepted, http::status::accepted);
      }));
}

}  // namespace corridor::server
