// Routes for localization: GET /api/v1/localization, PUT /api/v1/localization/pose, POST
// /api/v1/localization/relocalize, and, with the simulator, PUT /api/v1/sim/pose (a kidnapped robot); for mapping a
// new building: POST /api/v1/mapping/start and /stop, GET /api/v1/mapping and /api/v1/mapping/image.
#include <variant>

#include "server/api/api.h"
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

nav::Pose2 Api::ParsePoseOnMap(const json& body, const std::string& where) const {
  const nav::Pose2 pose{RequireNumber(body, "x", where), RequireNumber(body, "y", where),
                        nav::WrapAngle(RequireNumber(body, "yaw", where))};
  if (auto off = c_.core.OffMap(pose)) {
    throw ApiError(http::status::unprocessable_entity, "Pose outside the map", *off, "outside_map");
  }
  return pose;
}

void Api::AddLocalizationRoutes() {
  Add(http::verb::get, "/api/v1/localization", Access::kViewer, Sync([this](const Request& r, const Params&) {
        if (const auto state = c_.bus.Get(topics::kLocalization).latest()) return JsonResponse(r, ToJson(*state));
        // Not the filter (or no scan yet): what the pose topic says.
        json body{
            {"source", SourceName(c_.config.localization.source)},
            {"health", c_.config.localization.source == LocalizationOptions::Source::kSimTruth ? "ok" : "uncertain"},
            {"particle_count", 0},
            {"particles", json::array()}};
        if (const auto pose = c_.bus.Get(topics::kPose).latest()) body["pose"] = ToJson(pose->pose);
        return JsonResponse(r, body);
      }));
  // The pose is taken on localization's executor, which says how well the last scan fits the map there: a pose the
  // sensors contradict is taken, and the reply says so (the filter will likely move away from it).
  Add(http::verb::put, "/api/v1/localization/pose", Access::kOperator,
      [this](const Request& r, const Params&, Reply reply) {
        RequireLocalizing();
        const json body = ParseJsonBody(r);
        if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
        AllowOnlyKeys(body, {"x", "y", "yaw", "sigma_m", "sigma_yaw"}, "");
        PoseOrder order;
        order.pose = {RequireNumber(body, "x", ""), RequireNumber(body, "y", ""),
                      nav::WrapAngle(RequireNumber(body, "yaw", ""))};
        if (body.contains("sigma_m")) order.sigma_m = RequireNumber(body, "sigma_m", "");
        if (body.contains("sigma_yaw")) order.sigma_rad = RequireNumber(body, "sigma_yaw", "");
        order.origin = "rest";
        c_.core.SetPose(order, [this, r, reply, order](PoseResult result) {
          Answer(r, reply, [&]() -> Response {
            if (const auto* refused = std::get_if<PoseRefused>(&result)) {
              switch (refused->reason) {
                case PoseRefusal::kNotLocalizing:
                  throw ApiError(http::status::conflict, "Not localizing", refused->detail, "not_localizing");
                case PoseRefusal::kOutsideMap:
                  throw ApiError(http::status::unprocessable_entity, "Pose outside the map", refused->detail,
                                 "outside_map");
                case PoseRefusal::kBadSpread:
                  throw ApiError(http::status::bad_request, "Invalid request", refused->detail);
                case PoseRefusal::kBusy: throw ApiError(http::status::conflict, "Not now", refused->detail, "mapping");
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
          });
        });
      });
  Add(http::verb::post, "/api/v1/localization/relocalize", Access::kOperator,
      Sync([this](const Request& r, const Params&) {
        if (const auto refused = c_.core.Relocalize("rest")) ThrowMappingRefused(*refused);
        return JsonResponse(r, {{"relocalizing", true}}, http::status::accepted);
      }));
  Add(http::verb::put, "/api/v1/sim/pose", Access::kOperator, Sync([this](const Request& r, const Params&) {
        if (c_.sim == nullptr)
          throw ApiError(http::status::not_found, "No simulator", "only a simulated robot can be moved");
        const json body = ParseJsonBody(r);
        if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
        AllowOnlyKeys(body, {"x", "y", "yaw"}, "");
        const nav::Pose2 pose = ParsePoseOnMap(body, "");
        c_.sim->Teleport(pose);
        return JsonResponse(r, {{"pose", ToJson(pose)}});
      }));
  // The simulator's doors: what a building's door controller moves (it calls these as it would its door motors).
  const auto sim_doors = [this] {
    if (c_.sim == nullptr) throw ApiError(http::status::not_found, "No simulator", "only a simulated robot has these");
    json doors = json::array();
    for (const auto& [id, open] : c_.sim->doors()) doors.push_back({{"id", id}, {"open", open}});
    return doors;
  };
  Add(http::verb::get, "/api/v1/sim/doors", Access::kViewer, Sync([sim_doors](const Request& r, const Params&) {
        return JsonResponse(r, {{"doors", sim_doors()}});
      }));
  Add(http::verb::put, "/api/v1/sim/doors/{id}", Access::kOperator,
      Sync([this, sim_doors](const Request& r, const Params& p) {
        sim_doors();
        const json body = ParseJsonBody(r);
        if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
        AllowOnlyKeys(body, {"open"}, "");
        if (!body.contains("open") || !body["open"].is_boolean()) {
          throw ApiError(http::status::bad_request, "Invalid request", "'open' must be true or false");
        }
        const std::string& id = p.at("id");
        if (!c_.sim->SetDoorOpen(id, body["open"].get<bool>())) {
          throw ApiError(http::status::not_found, "No such door", "the simulator has no door '" + id + "'", "no_door");
        }
        return JsonResponse(r, {{"id", id}, {"open", body["open"]}});
      }));
  AddSimLiftRoutes();
  AddMappingRoutes();
}

void Api::AddSimLiftRoutes() {
  // The simulator's lifts: what a building's lift controller drives (it calls these as it would the lift's own
  // controls).
  const auto lift = [this](const std::string& id) {
    if (c_.sim == nullptr) throw ApiError(http::status::not_found, "No simulator", "only a simulated robot has these");
    for (const drivers::sim::SimLiftState& l : c_.sim->lifts()) {
      if (l.id == id) return l;
    }
    throw ApiError(http::status::not_found, "No such lift", "the simulator has no lift '" + id + "'", "no_lift");
  };
  const auto lift_json = [](const drivers::sim::SimLiftState& l) {
    return json{
        {"id", l.id}, {"floor", l.floor}, {"destination", l.destination}, {"door", l.door_open ? "open" : "closed"}};
  };
  Add(http::verb::get, "/api/v1/sim/lifts", Access::kViewer, Sync([this, lift_json](const Request& r, const Params&) {
        if (c_.sim == nullptr) {
          throw ApiError(http::status::not_found, "No simulator", "only a simulated robot has these");
        }
        json lifts = json::array();
        for (const drivers::sim::SimLiftState& l : c_.sim->lifts()) lifts.push_back(lift_json(l));
        return JsonResponse(r, {{"lifts", std::move(lifts)}});
      }));
  Add(http::verb::get, "/api/v1/sim/lifts/{id}", Access::kViewer,
      Sync([lift, lift_json](const Request& r, const Params& p) {
        return JsonResponse(r, lift_json(lift(p.at("id"))));
      }));
  Add(http::verb::put, "/api/v1/sim/lifts/{id}", Access::kOperator,
      Sync([this, lift, lift_json](const Request& r, const Params& p) {
        const std::string& id = p.at("id");
        lift(id);
        const json body = ParseJsonBody(r);
        if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
        AllowOnlyKeys(body, {"floor"}, "");
        if (!body.contains("floor") || !body["floor"].is_string() || body["floor"].get<std::string>().empty()) {
          throw ApiError(http::status::bad_request, "Invalid request", "'floor' must be the name of a floor");
        }
        const std::string floor = body["floor"].get<std::string>();
        if (!c_.sim->CallLift(id, floor)) {
          throw ApiError(http::status::unprocessable_entity, "No such floor",
                         "lift '" + id + "' does not stop at floor '" + floor + "'", "unknown_floor");
        }
        return JsonResponse(r, lift_json(lift(id)));
      }));
  Add(http::verb::post, "/api/v1/sim/lifts/{id}/release", Access::kOperator,
      Sync([this, lift, lift_json](const Request& r, const Params& p) {
        const std::string& id = p.at("id");
        lift(id);
        c_.sim->CallLift(id, "");
        return JsonResponse(r, lift_json(lift(id)));
      }));
}

void Api::AddMappingRoutes() {
  const auto mapping = [this] { return c_.bus.Get(topics::kMapping).latest(); };
  Add(http::verb::get, "/api/v1/mapping", Access::kViewer, Sync([this, mapping](const Request& r, const Params&) {
        const auto state = mapping();
        const auto explore = c_.bus.Get(topics::kExploreState).latest();
        return JsonResponse(r, MappingJson(state ? *state : MappingState{}, explore && explore->exploring));
      }));
  Add(http::verb::get, "/api/v1/mapping/image", Access::kViewer, Sync([mapping](const Request& r, const Params&) {
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
    if (const auto refused = c_.core.StartMapping(name, "rest")) ThrowMappingRefused(*refused);
    return name;
  };
  const auto object_body = [](const Request& r) {
    const json body = ParseJsonBody(r);
    if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "expected a JSON object");
    AllowOnlyKeys(body, {"name"}, "");
    return body;
  };
  Add(http::verb::post, "/api/v1/mapping/start", Access::kAdmin,
      Sync([start_mapping, object_body](const Request& r, const Params&) {
        return JsonResponse(r, {{"mapping", start_mapping(object_body(r))}}, http::status::accepted);
      }));
  // Exploring maps as it goes: under a new name, or within the mapping under way (no name then).
  Add(http::verb::post, "/api/v1/mapping/explore", Access::kAdmin,
      Sync([this, mapping, start_mapping, object_body](const Request& r, const Params&) {
        RequireLocalizing();
        const json body = object_body(r);
        const auto state = mapping();
        std::string name;
        if (state && state->active && !body.contains("name")) {
          name = state->name;
        } else {
          name = start_mapping(body);
        }
        if (const auto refused = c_.core.Explore("rest")) ThrowMappingRefused(*refused);
        return JsonResponse(r, {{"exploring", name}}, http::status::accepted);
      }));
  Add(http::verb::post, "/api/v1/mapping/stop", Access::kAdmin, Sync([this](const Request& r, const Params&) {
        const auto stopped = c_.core.StopMapping("rest");
        if (const auto* refused = std::get_if<MappingRefused>(&stopped)) ThrowMappingRefused(*refused);
        return JsonResponse(r, {{"saving", std::get<std::string>(stopped)}}, http::status::accepted);
      }));
}

void Api::RequireLocalizing() const {
  if (auto why = c_.core.NotLocalizing())
    throw ApiError(http::status::conflict, "Not localizing", *why, "not_localizing");
}

}  // namespace corridor::server
