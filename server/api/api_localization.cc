#include "server/api/api_localization.h"

#include <variant>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// The core's refusal as the problem it is over HTTP: always 409, the code naming the reason.
[[noreturn]] void ThrowMappingRefused(const MappingRefused& refused) {
  switch (refused.reason) {
    case MappingRefusal::kNotLocalizing:
      throw ApiError(http::status::conflict, "Not localizing", refused.detail, "not_localizing");
    case MappingRefusal::kMapExists: throw ApiError(http::status::conflict, "Map exists", refused.detail, "map_exists");
    case MappingRefusal::kAlreadyMapping:
      throw ApiError(http::status::conflict, "Already mapping", refused.detail, "already_mapping");
    case MappingRefusal::kNotMapping:
      throw ApiError(http::status::conflict, "Not mapping", refused.detail, "not_mapping");
  }
  throw ApiError(http::status::conflict, "Refused", refused.detail);
}

using auth::Access;
using nlohmann::json;

const char* SourceName(LocalizationOptions::Source source) {
  switch (source) {
    case LocalizationOptions::Source::kOdometry: return "odometry";
    case LocalizationOptions::Source::kSimTruth: return "sim_truth";
    case LocalizationOptions::Source::kMonteCarlo: return "mcl";
  }
  return "unknown";
}

json MappingJson(const MappingState& m, bool exploring) {
  json body{{"active", m.active},   {"exploring", exploring && m.active}, {"name", m.name},   {"scans", m.scans},
            {"submaps", m.submaps}, {"loop_closures", m.loop_closures},   {"saved", m.saved}, {"error", m.error},
            {"map", nullptr}};
  if (m.grid) {
    body["map"] = {{"revision", m.revision},
                   {"resolution_m", m.grid->resolution_m()},
                   {"width", m.grid->width()},
                   {"height", m.grid->height()},
                   {"origin", ToJson(m.grid->origin())},
                   {"image_url", "/api/v1/mapping/image?revision=" + std::to_string(m.revision)}};
  }
  return body;
}

}  // namespace

LocalizationApi::LocalizationApi(Bus& bus, const RobotCore& core, const LocalizationOptions& options)
    : bus_(bus), core_(core), options_(options) {}

void LocalizationApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/localization", Access::kViewer, Sync([this](const Request& r, const Params&) {
               if (const auto state = bus_.Get(topics::kLocalization).latest()) return JsonResponse(r, ToJson(*state));
               // Not the filter (or no scan yet): what the pose topic says.
               json body{{"source", SourceName(options_.source)},
                         {"health", options_.source == LocalizationOptions::Source::kSimTruth ? "ok" : "uncertain"},
                         {"particle_count", 0},
                         {"particles", json::array()}};
               if (const auto pose = bus_.Get(topics::kPose).latest()) body["pose"] = ToJson(pose->pose);
               return JsonResponse(r, body);
             }));
  // The pose is taken on localization's executor, which says how well the last scan fits the map there: a pose the
  // sensors contradict is taken, and the reply says so (the filter will likely move away from it).
  routes.Add(http::verb::put, "/api/v1/localization/pose", Access::kOperator,
             [this](const Request& r, const Params&, Reply reply) {
               RequireLocalizing(core_);
               const json body = ObjectBody(r, {"x", "y", "yaw", "sigma_m", "sigma_yaw"});
               PoseOrder order;
               order.pose = {RequireNumber(body, "x", ""), RequireNumber(body, "y", ""),
                             nav::WrapAngle(RequireNumber(body, "yaw", ""))};
               if (body.contains("sigma_m")) order.sigma_m = RequireNumber(body, "sigma_m", "");
               if (body.contains("sigma_yaw")) order.sigma_rad = RequireNumber(body, "sigma_yaw", "");
               order.origin = "rest";
               core_.SetPose(order, [r, reply, order](PoseResult result) {
                 reply(Respond(r, [&]() -> Response {
                   if (const auto* refused = std::get_if<PoseRefused>(&result)) {
                     switch (refused->reason) {
                       case PoseRefusal::kNotLocalizing:
                         throw ApiError(http::status::conflict, "Not localizing", refused->detail, "not_localizing");
                       case PoseRefusal::kOutsideMap:
                         throw ApiError(http::status::unprocessable_entity, "Pose outside the map", refused->detail,
                                        "outside_map");
                       case PoseRefusal::kBadSpread:
                         throw ApiError(http::status::bad_request, "Invalid request", refused->detail);
                       case PoseRefusal::kBusy:
                         throw ApiError(http::status::conflict, "Not now", refused->detail, "mapping");
                     }
                   }
                   const PoseCheck& check = std::get<PoseCheck>(result);
                   json answer{{"pose", ToJson(order.pose)},
                               {"sigma_m", order.sigma_m},
                               {"sigma_yaw", order.sigma_rad},
                               {"agrees", check.agrees},
                               {"detail", check.detail}};
                   answer["agreement"] = check.checked ? json(check.agreement) : json(nullptr);
                   answer["agreement_before"] = check.checked ? json(check.agreement_before) : json(nullptr);
                   return JsonResponse(r, answer, http::status::accepted);
                 }));
               });
             });
  routes.Add(http::verb::post, "/api/v1/localization/relocalize", Access::kOperator,
             Sync([this](const Request& r, const Params&) {
               if (const auto refused = core_.Relocalize("rest")) ThrowMappingRefused(*refused);
               return JsonResponse(r, {{"relocalizing", true}}, http::status::accepted);
             }));
  AddMappingRoutes(routes);
}

void LocalizationApi::AddMappingRoutes(Router& routes) const {
  const auto mapping = [this] { return bus_.Get(topics::kMapping).latest(); };
  routes.Add(http::verb::get, "/api/v1/mapping", Access::kViewer,
             Sync([this, mapping](const Request& r, const Params&) {
               const auto state = mapping();
               const auto explore = bus_.Get(topics::kExploreState).latest();
               return JsonResponse(r, MappingJson(state ? *state : MappingState{}, explore && explore->exploring));
             }));
  routes.Add(
      http::verb::get, "/api/v1/mapping/image", Access::kViewer, Sync([mapping](const Request& r, const Params&) {
        const auto state = mapping();
        if (!state || !state->grid) {
          throw ApiError(http::status::not_found, "No map being built", "start mapping, then drive a little", "no_map");
        }
        return MakeResponse(r, http::status::ok, "image/png", EncodePng(*state->grid));
      }));
  // Mapping starts under a new map's name (400 for a bad one, 409 if it is taken or mapping is under way).
  const auto start_mapping = [this](const json& body) {
    if (!body.contains("name") || !body["name"].is_string() || !ValidMapName(body["name"].get<std::string>())) {
      throw ApiError(http::status::bad_request, "Invalid request",
                     "name: a map name of letters, digits, '-', '_' and '.' (at most 64, not starting with '.')");
    }
    const std::string name = body["name"].get<std::string>();
    if (const auto refused = core_.StartMapping(name, "rest")) ThrowMappingRefused(*refused);
    return name;
  };
  routes.Add(http::verb::post, "/api/v1/mapping/start", Access::kAdmin,
             Sync([start_mapping](const Request& r, const Params&) {
               return JsonResponse(r, {{"mapping", start_mapping(ObjectBody(r, {"name"}))}}, http::status::accepted);
             }));
  // Exploring maps as it goes: under a new name, or within the mapping under way (no name then).
  routes.Add(http::verb::post, "/api/v1/mapping/explore", Access::kAdmin,
             Sync([this, mapping, start_mapping](const Request& r, const Params&) {
               RequireLocalizing(core_);
               const json body = ObjectBody(r, {"name"});
               const auto state = mapping();
               std::string name;
               if (state && state->active && !body.contains("name")) {
                 name = state->name;
               } else {
                 name = start_mapping(body);
               }
               if (const auto refused = core_.Explore("rest")) ThrowMappingRefused(*refused);
               return JsonResponse(r, {{"exploring", name}}, http::status::accepted);
             }));
  routes.Add(http::verb::post, "/api/v1/mapping/stop", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               const auto stopped = core_.StopMapping("rest");
               if (const auto* refused = std::get_if<MappingRefused>(&stopped)) ThrowMappingRefused(*refused);
               return JsonResponse(r, {{"saving", std::get<std::string>(stopped)}}, http::status::accepted);
             }));
}

void RequireLocalizing(const RobotCore& core) {
  if (auto why = core.NotLocalizing()) throw ApiError(http::status::conflict, "Not localizing", *why, "not_localizing");
}

}  // namespace corridor::server
