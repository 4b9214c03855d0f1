#include "server/api/api_map.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "nav/mission/docking.h"
#include "server/fleet/doors.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// The library's refusal of a map library request as the API's: what about decides the status.
ApiError LibraryRefusal(const MapEditError& e) {
  using Kind = MapEditError::Kind;
  switch (e.kind()) {
    case Kind::kUnknownMap: return {http::status::not_found, "Not found", e.what()};
    case Kind::kNameTaken: return {http::status::conflict, "Name taken", e.what(), "name_taken"};
    case Kind::kInUse: return {http::status::conflict, "Map in use", e.what(), "map_in_use"};
    case Kind::kConfigured: return {http::status::conflict, "Configured map", e.what(), "map_configured"};
    case Kind::kBadName: return {http::status::unprocessable_entity, "Invalid name", e.what(), "invalid_name"};
    case Kind::kInvalid: break;
  }
  return {http::status::unprocessable_entity, "Invalid map", e.what(), "invalid_map"};
}

using auth::Access;
using nlohmann::json;

// The most cells one edit may set: a full-map repaint goes through PUT /api/v1/map/image instead.
constexpr std::size_t kMaxCellEdits = 250000;

json ZoneJson(const nav::Zone& z) {
  json polygon = json::array();
  for (const auto& p : z.polygon) polygon.push_back({p.x(), p.y()});
  json j = {{"id", z.id}, {"name", z.name}, {"kind", nav::ToString(z.kind)}, {"polygon", polygon}};
  if (z.kind == nav::ZoneKind::kSpeedLimit) j["max_speed_mps"] = z.max_speed_mps;
  return j;
}

// Traffic costs (per cell, row-major from the map's origin) as a BGRA PNG over the map image: one red, its alpha
// from 0 (no cost) to 200 at the highest cost, so that the map stays readable under it.
std::string TrafficImage(const std::vector<float>& cost, int width, int height) {
  const float highest = std::max(*std::max_element(cost.begin(), cost.end()), 1e-6f);
  cv::Mat image(height, width, CV_8UC4, cv::Scalar(0x2e, 0x22, 0xcf, 0));
  for (int y = 0; y < height; ++y) {
    auto* row = image.ptr<cv::Vec4b>(height - 1 - y);
    for (int x = 0; x < width; ++x) {
      const float c = cost[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
      row[x][3] = static_cast<std::uint8_t>(std::lround(200.0f * std::clamp(c / highest, 0.0f, 1.0f)));
    }
  }
  std::vector<std::uint8_t> png;
  cv::imencode(".png", image, png);
  return {png.begin(), png.end()};
}

json PlaceJson(const nav::Place& p, const nav::DockGeometry& dock) {
  json j = {{"id", p.id},      {"name", p.name},        {"x", p.pose.x_m},
            {"y", p.pose.y_m}, {"yaw", p.pose.yaw_rad}, {"kind", nav::ToString(p.kind)}};
  if (p.kind == nav::PlaceKind::kDock) j["staging"] = ToJson(nav::StagingPose(p.pose, dock));
  return j;
}

nav::Zone ParseZone(const json& body, std::string id) {
  AllowOnlyKeys(body, {"id", "name", "kind", "polygon", "max_speed_mps"}, "");
  nav::Zone z;
  z.id = std::move(id);
  if (body.contains("name") && !body["name"].is_string()) {
    throw ApiError(http::status::bad_request, "Invalid zone", "'name' must be a string");
  }
  z.name = body.value("name", "");
  if (!body.contains("kind") || !body["kind"].is_string()) {
    throw ApiError(http::status::bad_request, "Invalid zone", "'kind' must be \"keep_out\" or \"speed_limit\"");
  }
  const auto kind = nav::ZoneKindFromString(body["kind"].get<std::string>());
  if (!kind)
    throw ApiError(http::status::bad_request, "Invalid zone", "'kind' must be \"keep_out\" or \"speed_limit\"");
  z.kind = *kind;
  const auto polygon = body.find("polygon");
  if (polygon == body.end() || !polygon->is_array() || polygon->size() > 1000) {
    throw ApiError(http::status::bad_request, "Invalid zone", "'polygon' must be a list of up to 1000 [x, y] points");
  }
  for (const json& p : *polygon) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      throw ApiError(http::status::bad_request, "Invalid zone", "'polygon' points are [x, y] number pairs");
    }
    z.polygon.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  if (z.kind == nav::ZoneKind::kSpeedLimit) z.max_speed_mps = RequireNumber(body, "max_speed_mps", "");
  try {
    nav::Validate(z);
  } catch (const nav::InvalidZone& e) {
    throw ApiError(http::status::bad_request, "Invalid zone", e.what());
  }
  return z;
}

nav::Place ParsePlace(const json& body, std::string id) {
  AllowOnlyKeys(body, {"id", "name", "x", "y", "yaw", "kind", "staging"}, "");
  if (!body.contains("name") || !body["name"].is_string() || body["name"].get<std::string>().empty()) {
    throw ApiError(http::status::bad_request, "Invalid place", "'name' must be a non-empty string");
  }
  if (body.contains("id") && !body["id"].is_string()) {
    throw ApiError(http::status::bad_request, "Invalid place",
                   "'id' (ignored: the path's or a new one) must be a string");
  }
  if (body.contains("staging") && !body["staging"].is_object()) {
    throw ApiError(http::status::bad_request, "Invalid place",
                   "'staging' (ignored: it follows from the pose) must be an object");
  }
  nav::PlaceKind kind = nav::PlaceKind::kPlace;
  if (body.contains("kind")) {
    const auto parsed =
        body["kind"].is_string() ? nav::PlaceKindFromString(body["kind"].get<std::string>()) : std::nullopt;
    if (!parsed) throw ApiError(http::status::bad_request, "Invalid place", "'kind' must be \"place\" or \"dock\"");
    kind = *parsed;
  }
  return {std::move(id),
          body["name"].get<std::string>(),
          {RequireNumber(body, "x", ""), RequireNumber(body, "y", ""),
           body.contains("yaw") ? nav::WrapAngle(RequireNumber(body, "yaw", "")) : 0.0},
          kind};
}

// Why no mission could go to `place` on `costmap`, or nullopt.
std::optional<std::string> PlaceProblem(const nav::Costmap& costmap, const nav::Place& place,
                                        const nav::DockGeometry& dock) {
  const auto cell = costmap.grid().WorldToCell(place.pose.translation());
  if (!cell) return "the place is outside the map";
  const std::size_t i = costmap.Index(*cell);
  if (place.kind == nav::PlaceKind::kDock) {
    if (costmap.IsObstacle(i)) return "the docked pose is on a wall, unknown space or in a keep-out zone";
    if (const auto why = nav::DockUnreachable(costmap, place.pose, dock)) return "no mission can dock there: " + *why;
    return std::nullopt;
  }
  if (costmap.Traversable(i)) return std::nullopt;
  if (costmap.InKeepOut(i)) return "the place is in a keep-out zone";
  if (costmap.IsObstacle(i)) return "the place is on a wall or in unknown space";
  return "the place is too close to a wall for the robot";
}

void ExpectMapEdit(const std::function<void()>& edit) {
  try {
    edit();
  } catch (const MapEditError& e) {
    throw ApiError(http::status::unprocessable_entity, "Invalid map edit", e.what(), "invalid_map_edit");
  }
}

}  // namespace

MapApi::MapApi(Bus& bus, const RobotCore& core, const Config& config, MapLibrary& maps, Store& store,
               PlannerService& planner, OctreeNode* octree, bool simulated, Executor& io)
    : bus_(bus),
      core_(core),
      config_(config),
      maps_(maps),
      store_(store),
      planner_(planner),
      octree_(octree),
      simulated_(simulated),
      io_(io) {}

void MapApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/map", Access::kViewer, Sync([this](const Request& r, const Params&) {
               const auto map = maps_.active();
               const nav::OccupancyGrid& g = map->grid;
               return JsonResponse(r, {{"name", map->name},
                                       {"revision", map->revision},
                                       {"resolution_m", g.resolution_m()},
                                       {"width", g.width()},
                                       {"height", g.height()},
                                       {"origin", ToJson(g.origin())},
                                       {"image_url", "/api/v1/map/image?revision=" + std::to_string(map->revision)}});
             }));
  // The building: its floors (each with its map), the floor the robot is on, and the lifts between them.
  routes.Add(
      http::verb::get, "/api/v1/building", Access::kViewer, Sync([this](const Request& r, const Params&) {
        const nav::Building building = CurrentBuilding(config_, store_);
        const nav::Floor* here = building.FloorOfMap(maps_.active()->name);
        json floors = json::array();
        for (const nav::Floor& f : building.floors) {
          json places = json::array();
          for (const nav::Place& p : store_.Places(f.map)) {
            places.push_back(PlaceJson(p, config_.mission.docking.dock));
          }
          floors.push_back({{"name", f.name}, {"map", f.map}, {"places", std::move(places)}});
        }
        json lifts = json::array();
        for (const nav::Lift& l : building.lifts) {
          json stops = json::array();
          for (const nav::LiftStop& s : l.stops) {
            stops.push_back(
                {{"floor", s.floor},
                 {"door", {{"x1", s.door.a.x()}, {"y1", s.door.a.y()}, {"x2", s.door.b.x()}, {"y2", s.door.b.y()}}},
                 {"lobby", ToJson(s.lobby)},
                 {"car", ToJson(nav::CarPose(l, s))}});
          }
          lifts.push_back({{"id", l.id},
                           {"car_width_m", l.car_width_m},
                           {"car_depth_m", l.car_depth_m},
                           {"stops", std::move(stops)}});
        }
        return JsonResponse(r, {{"name", building.name},
                                {"floor", here != nullptr ? json(here->name) : json(nullptr)},
                                {"floors", std::move(floors)},
                                {"lifts", std::move(lifts)}});
      }));
  // The doors on the map in use (the configuration's, and the simulator's on its world's map) and what their
  // controller says of those a mission asked for.
  const auto doors_here = [this] {
    const std::string map = maps_.active()->name;
    return DoorsOfMap(config_, store_.Doors(map), map, simulated_);
  };
  const auto door_json = [this](const MapDoor& d) {
    const auto states = bus_.Get(topics::kDoorStates).latest();
    std::string state = "idle";
    if (states && states->doors.contains(d.door.id)) state = nav::ToString(states->doors.at(d.door.id).status);
    return json{{"id", d.door.id},    {"x1", d.door.a.x()}, {"y1", d.door.a.y()}, {"x2", d.door.b.x()},
                {"y2", d.door.b.y()}, {"source", d.source}, {"state", state}};
  };
  routes.Add(http::verb::get, "/api/v1/doors", Access::kViewer,
             Sync([this, doors_here, door_json](const Request& r, const Params&) {
               json out = json::array();
               for (const MapDoor& d : doors_here()) out.push_back(door_json(d));
               return JsonResponse(
                   r, {{"map", maps_.active()->name}, {"controlled", DoorsAnswer(config_)}, {"doors", std::move(out)}});
             }));
  // A door drawn on the map in use: a line across a passage, with an id its controller knows.
  routes.Add(
      http::verb::post, "/api/v1/doors", Access::kAdmin,
      Sync([this, doors_here, door_json](const Request& r, const Params&) {
        const json body = ObjectBody(r, {"id", "x1", "y1", "x2", "y2"});
        if (!body.contains("id") || !body["id"].is_string() || body["id"].get<std::string>().empty() ||
            body["id"].get<std::string>().size() > 64) {
          throw ApiError(http::status::bad_request, "Invalid request",
                         "'id' must be the door's id (1 to 64 characters)");
        }
        nav::Door door{body["id"].get<std::string>(),
                       {RequireNumber(body, "x1", ""), RequireNumber(body, "y1", "")},
                       {RequireNumber(body, "x2", ""), RequireNumber(body, "y2", "")}};
        const double length = (door.b - door.a).norm();
        if (length < 0.3 || length > 20.0) {
          throw ApiError(http::status::unprocessable_entity, "Not a door", "a door is 0.3 to 20 m across", "bad_door");
        }
        const nav::OccupancyGrid& grid = maps_.active()->grid;
        if (!grid.WorldToCell(door.a) || !grid.WorldToCell(door.b)) {
          throw ApiError(http::status::unprocessable_entity, "Door outside the map", "both ends must be on the map",
                         "goal_outside_map");
        }
        for (const MapDoor& d : doors_here()) {
          if (d.door.id == door.id) {
            throw ApiError(http::status::conflict, "Id taken", "a door '" + door.id + "' is on this map", "name_taken");
          }
        }
        store_.PutDoor(maps_.active()->name, door);
        core_.MapEdited("doors", "rest");
        return JsonResponse(r, door_json({door, "drawn"}), http::status::created);
      }));
  routes.Add(http::verb::delete_, "/api/v1/doors/{id}", Access::kAdmin,
             Sync([this, doors_here](const Request& r, const Params& p) {
               const std::string& id = p.at("id");
               if (!store_.DeleteDoor(maps_.active()->name, id)) {
                 for (const MapDoor& d : doors_here()) {
                   if (d.door.id == id) {
                     throw ApiError(http::status::conflict, "Configured door",
                                    "door '" + id + "' is in the configuration (doors.list or sim.doors), not drawn",
                                    "configured");
                   }
                 }
                 throw ApiError(http::status::not_found, "Not found", "no door " + id + " on this map");
               }
               core_.MapEdited("doors", "rest");
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));
  // A lift's stop on a floor, drawn in the console: its door there and the lobby facing it.
  routes.Add(http::verb::put, "/api/v1/building/lifts/{id}/stops/{floor}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               const std::string& id = p.at("id");
               if (id.empty() || id.size() > 64 ||
                   id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                        "0123456789_.-") != std::string::npos) {
                 throw ApiError(http::status::bad_request, "Invalid request",
                                "a lift's id is 1 to 64 letters, digits, '_', '.' or '-'");
               }
               const json body = ObjectBody(r, {"x1", "y1", "x2", "y2", "lobby"});
               if (!body.contains("lobby"))
                 throw ApiError(http::status::bad_request, "Invalid request", "missing 'lobby'");
               const json& lobby = body["lobby"];
               if (!lobby.is_object())
                 throw ApiError(http::status::bad_request, "Invalid request", "'lobby' must be a pose");
               AllowOnlyKeys(lobby, {"x", "y", "yaw"}, "lobby");
               nav::LiftStop stop{p.at("floor"),
                                  {"",
                                   {RequireNumber(body, "x1", ""), RequireNumber(body, "y1", "")},
                                   {RequireNumber(body, "x2", ""), RequireNumber(body, "y2", "")}},
                                  {RequireNumber(lobby, "x", "lobby"), RequireNumber(lobby, "y", "lobby"),
                                   nav::WrapAngle(RequireNumber(lobby, "yaw", "lobby"))}};
               try {
                 nav::ValidateStop(CurrentBuilding(config_, store_), stop);
               } catch (const std::invalid_argument& e) {
                 throw ApiError(http::status::unprocessable_entity, "Not a lift stop", e.what(), "bad_lift_stop");
               }
               store_.PutLiftStop(id, stop);
               core_.MapEdited("lift stops", "rest");
               const nav::Building building = CurrentBuilding(config_, store_);
               const nav::Lift* lift = building.LiftNamed(id);
               return JsonResponse(r, {{"id", id}, {"stops", lift->stops.size()}});
             }));
  routes.Add(http::verb::delete_, "/api/v1/building/lifts/{id}/stops/{floor}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               if (!store_.DeleteLiftStop(p.at("id"), p.at("floor"))) {
                 throw ApiError(http::status::not_found, "Not found",
                                "no stop of lift " + p.at("id") + " on floor " + p.at("floor") +
                                    " was drawn (the configuration's lifts stay)");
               }
               core_.MapEdited("lift stops", "rest");
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));
  routes.Add(http::verb::get, "/api/v1/map/image", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return MakeResponse(r, http::status::ok, "image/png", maps_.active()->png);
             }));
  // Where people have been walking, as the planner weighs it: a red overlay for the map image (its size, row 0 at
  // the top), most opaque where the extra cost is highest.
  routes.Add(
      http::verb::get, "/api/v1/map/traffic", Access::kViewer, Sync([this](const Request& r, const Params&) {
        const auto cost = planner_.traffic();
        const nav::OccupancyGrid& grid = maps_.active()->grid;
        if (!cost || cost->size() != static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height())) {
          throw ApiError(http::status::not_found, "No traffic", "nobody has been seen walking on this map lately");
        }
        return MakeResponse(r, http::status::ok, "image/png", TrafficImage(*cost, grid.width(), grid.height()));
      }));
  // The 3D map (server/nodes/octree_node.h): what it is, the OctoMap binary (.bt, for octovis or ROS's
  // octomap_server), and its occupied voxels for drawing (little-endian float32 x, y, z, size per voxel, map frame).
  // The snapshot is taken on the mapping executor, which answers.
  using SnapshotResponse = std::function<Response(const Request&, const OctreeSnapshot&)>;
  const auto octree_route = [this, &routes](const std::string& path, SnapshotResponse respond) {
    routes.Add(http::verb::get, path, Access::kViewer, [this, respond](const Request& r, const Params&, Reply reply) {
      if (octree_ == nullptr) {
        throw ApiError(http::status::not_found, "No 3D map", "the 3D map is off (octomap.enabled in the configuration)",
                       "no_octomap");
      }
      octree_->Snapshot([r, reply, respond](std::shared_ptr<const OctreeSnapshot> snapshot) {
        reply(Respond(r, [&]() -> Response {
          if (!snapshot) throw ApiError(http::status::not_found, "No 3D map", "there is no map yet", "no_octomap");
          return respond(r, *snapshot);
        }));
      });
    });
  };
  octree_route("/api/v1/map/octomap", [](const Request& r, const OctreeSnapshot& o) {
    const std::string query = "?revision=" + std::to_string(o.revision);
    return JsonResponse(r, {{"map", o.map},
                            {"revision", o.revision},
                            {"resolution_m", o.resolution_m},
                            {"leaves", o.leaves},
                            {"occupied", o.voxels.size() / 4},
                            {"bt_url", "/api/v1/map/octomap.bt" + query},
                            {"voxels_url", "/api/v1/map/octomap/voxels" + query}});
  });
  octree_route("/api/v1/map/octomap.bt", [](const Request& r, const OctreeSnapshot& o) {
    Response response = MakeResponse(r, http::status::ok, "application/octet-stream", o.bt);
    response.set(http::field::content_disposition, "attachment; filename=\"" + o.map + ".bt\"");
    return response;
  });
  octree_route("/api/v1/map/octomap/voxels", [](const Request& r, const OctreeSnapshot& o) {
    static_assert(std::endian::native == std::endian::little, "voxels are sent as little-endian float32");
    std::string bytes(o.voxels.size() * sizeof(float), '\0');
    std::memcpy(bytes.data(), o.voxels.data(), bytes.size());
    return MakeResponse(r, http::status::ok, "application/octet-stream", std::move(bytes));
  });
  routes.Add(http::verb::put, "/api/v1/map/image", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               ExpectMapEdit([&] { maps_.ReplaceImage(r.body()); });
               return JsonResponse(r, {{"revision", maps_.active()->revision}});
             }));
  routes.Add(
      http::verb::put, "/api/v1/map/cells", Access::kAdmin, Sync([this](const Request& r, const Params&) {
        const json body = ParseJsonBody(r);
        AllowOnlyKeys(body, {"cells", "rects"}, "");
        std::vector<CellEdit> edits;
        const auto value_of = [](const json& v, const std::string& where) {
          if (!v.is_number_integer()) {
            throw ApiError(http::status::bad_request, "Invalid map edit", where + ": value must be -1, 0 or 100");
          }
          return static_cast<std::int8_t>(std::clamp<std::int64_t>(v.get<std::int64_t>(), -2, 101));
        };
        for (const json& c : body.value("cells", json::array())) {
          if (!c.is_array() || c.size() != 3 || !c[0].is_number_integer() || !c[1].is_number_integer()) {
            throw ApiError(http::status::bad_request, "Invalid map edit", "cells are [column, row, value] triples");
          }
          edits.push_back({c[0].get<int>(), c[1].get<int>(), value_of(c[2], "cells")});
          if (edits.size() > kMaxCellEdits) break;
        }
        // Rectangles: {"x0", "y0", "x1", "y1", "value"}, inclusive cell ranges; what a brush stroke sends.
        for (const json& rect : body.value("rects", json::array())) {
          if (!rect.is_object()) throw ApiError(http::status::bad_request, "Invalid map edit", "rects are objects");
          const int x0 = static_cast<int>(RequireNumber(rect, "x0", "rects"));
          const int y0 = static_cast<int>(RequireNumber(rect, "y0", "rects"));
          const int x1 = static_cast<int>(RequireNumber(rect, "x1", "rects"));
          const int y1 = static_cast<int>(RequireNumber(rect, "y1", "rects"));
          const std::int8_t value = value_of(rect.value("value", json()), "rects");
          const auto area = static_cast<double>(std::abs(x1 - x0) + 1) * (std::abs(y1 - y0) + 1);
          if (area + static_cast<double>(edits.size()) > kMaxCellEdits) break;
          for (int y = std::min(y0, y1); y <= std::max(y0, y1); ++y) {
            for (int x = std::min(x0, x1); x <= std::max(x0, x1); ++x) edits.push_back({x, y, value});
          }
        }
        if (edits.size() > kMaxCellEdits) {
          throw ApiError(http::status::payload_too_large, "Edit too large",
                         "at most " + std::to_string(kMaxCellEdits) + " cells per edit; use PUT /api/v1/map/image");
        }
        ExpectMapEdit([&] { maps_.EditCells(edits); });
        return JsonResponse(r, {{"revision", maps_.active()->revision}, {"changed", edits.size()}});
      }));
  routes.Add(http::verb::get, "/api/v1/maps", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"maps", maps_.Names()}, {"active", maps_.active()->name}});
             }));
  routes.Add(
      http::verb::put, "/api/v1/map/active", Access::kAdmin, Sync([this](const Request& r, const Params&) {
        const json body = ParseJsonBody(r);
        AllowOnlyKeys(body, {"name"}, "");
        if (!body.contains("name") || !body["name"].is_string()) {
          throw ApiError(http::status::bad_request, "Invalid request", "'name' must be a map name");
        }
        if (const auto refused = core_.SelectMap(body["name"].get<std::string>(), "rest")) {
          if (refused->reason == MapRefusal::kMissionInProgress) {
            throw ApiError(http::status::conflict, "Mission in progress", refused->detail, "mission_in_progress");
          }
          throw ApiError(http::status::unprocessable_entity, "Invalid map edit", refused->detail, "invalid_map_edit");
        }
        return JsonResponse(r, {{"active", maps_.active()->name}});
      }));

  // The map library: a map imported from map_server files, renamed or deleted (with what belongs to it: its zones,
  // places and doors), and exported as map_server files.
  const auto string_of = [](const json& body, const char* key) {
    if (!body.contains(key) || !body[key].is_string()) {
      throw ApiError(http::status::bad_request, "Invalid request", std::string("'") + key + "' must be a string");
    }
    return body[key].get<std::string>();
  };
  // The map being made will be saved under its name: nothing may take it first.
  const auto not_being_made = [this](const std::string& name) {
    const auto mapping = bus_.Get(topics::kMapping).latest();
    if (mapping && mapping->active && mapping->name == name) {
      throw ApiError(http::status::conflict, "Name taken", "a map named '" + name + "' is being made", "name_taken");
    }
  };
  routes.Add(
      http::verb::post, "/api/v1/maps", Access::kAdmin,
      Sync([this, string_of, not_being_made](const Request& r, const Params&) {
        const json body = ObjectBody(r, {"name", "yaml", "image"});
        const std::string name = string_of(body, "name");
        not_being_made(name);
        const std::optional<std::string> image = FromBase64(string_of(body, "image"));
        if (!image) throw ApiError(http::status::bad_request, "Invalid request", "'image' must be base64");
        try {
          maps_.Import(name, string_of(body, "yaml"), *image);
        } catch (const MapEditError& e) {
          throw LibraryRefusal(e);
        }
        spdlog::info("map '{}' imported", name);
        return JsonResponse(r, {{"maps", maps_.Names()}, {"active", maps_.active()->name}}, http::status::created);
      }));
  routes.Add(http::verb::patch, "/api/v1/maps/{name}", Access::kAdmin,
             Sync([this, string_of, not_being_made](const Request& r, const Params& p) {
               const std::string& from = p.at("name");
               const std::string to = string_of(ObjectBody(r, {"name"}), "name");
               not_being_made(to);
               try {
                 maps_.Rename(from, to);
               } catch (const MapEditError& e) {
                 throw LibraryRefusal(e);
               }
               store_.RenameMap(from, to);
               spdlog::info("map '{}' renamed '{}'", from, to);
               return JsonResponse(r, {{"maps", maps_.Names()}, {"active", maps_.active()->name}});
             }));
  routes.Add(http::verb::delete_, "/api/v1/maps/{name}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               const std::string& name = p.at("name");
               try {
                 maps_.Delete(name);
               } catch (const MapEditError& e) {
                 throw LibraryRefusal(e);
               }
               store_.DeleteMap(name);
               spdlog::info("map '{}' deleted", name);
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));
  routes.Add(http::verb::get, "/api/v1/maps/{name}/files", Access::kViewer,
             Sync([this](const Request& r, const Params& p) {
               const std::string& name = p.at("name");
               try {
                 const auto [yaml, png] = maps_.Files(name);
                 return JsonResponse(
                     r, {{"name", name}, {"yaml", yaml}, {"image_name", name + ".png"}, {"image", ToBase64(png)}});
               } catch (const MapEditError& e) {
                 throw LibraryRefusal(e);
               }
             }));

  // Zones and places belong to the active map.
  routes.Add(http::verb::get, "/api/v1/zones", Access::kViewer, Sync([this](const Request& r, const Params&) {
               json zones = json::array();
               for (const nav::Zone& z : store_.Zones(maps_.active()->name)) zones.push_back(ZoneJson(z));
               return JsonResponse(r, {{"zones", zones}});
             }));
  routes.Add(http::verb::post, "/api/v1/zones", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               const nav::Zone z = ParseZone(ParseJsonBody(r), NewId());
               store_.PutZone(maps_.active()->name, z);
               core_.MapEdited("zones", "rest");
               Response res = JsonResponse(r, ZoneJson(z), http::status::created);
               res.set(http::field::location, "/api/v1/zones/" + z.id);
               return res;
             }));
  const auto find_zone = [this](const std::string& id) {
    for (const nav::Zone& z : store_.Zones(maps_.active()->name)) {
      if (z.id == id) return z;
    }
    throw ApiError(http::status::not_found, "Not found", "no zone " + id);
  };
  routes.Add(http::verb::get, "/api/v1/zones/{id}", Access::kViewer,
             Sync([find_zone](const Request& r, const Params& p) {
               return JsonResponse(r, ZoneJson(find_zone(p.at("id"))));
             }));
  routes.Add(http::verb::put, "/api/v1/zones/{id}", Access::kAdmin,
             Sync([this, find_zone](const Request& r, const Params& p) {
               find_zone(p.at("id"));
               const nav::Zone z = ParseZone(ParseJsonBody(r), p.at("id"));
               store_.PutZone(maps_.active()->name, z);
               core_.MapEdited("zones", "rest");
               return JsonResponse(r, ZoneJson(z));
             }));
  routes.Add(http::verb::delete_, "/api/v1/zones/{id}", Access::kAdmin, Sync([this](const Request& r, const Params& p) {
               if (!store_.DeleteZone(maps_.active()->name, p.at("id"))) {
                 throw ApiError(http::status::not_found, "Not found", "no zone " + p.at("id"));
               }
               core_.MapEdited("zones", "rest");
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));

  routes.Add(http::verb::get, "/api/v1/places", Access::kViewer, Sync([this](const Request& r, const Params&) {
               json places = json::array();
               for (const nav::Place& p : store_.Places(maps_.active()->name))
                 places.push_back(PlaceJson(p, config_.mission.docking.dock));
               return JsonResponse(r, {{"places", places}});
             }));
  const auto check_name_free = [this](const nav::Place& place) {
    for (const nav::Place& p : store_.Places(maps_.active()->name)) {
      if (p.name == place.name && p.id != place.id) {
        throw ApiError(http::status::conflict, "Name taken", "a place named '" + place.name + "' exists", "name_taken");
      }
    }
    const auto cell = maps_.active()->grid.WorldToCell(place.pose.translation());
    if (!cell) {
      throw ApiError(http::status::unprocessable_entity, "Place outside the map", "the place is outside the map",
                     "goal_outside_map");
    }
  };
  // A place is somewhere a mission can go: on the planner's costmap (the map, its zones, what the 3D map found), free
  // and clear of walls by the robot's radius, as a goal must be; a dock, its staging pose so (nav::DockUnreachable),
  // with the docked pose itself off any obstacle. Then it is stored, on the io executor.
  const auto put_place = [this, check_name_free](const Request& r, Reply reply, nav::Place place, bool made) {
    check_name_free(place);
    planner_.WithCostmap([this, r, reply, place = std::move(place), made, check_name_free](
                             std::shared_ptr<const nav::Costmap> costmap, std::uint64_t) {
      const auto problem = PlaceProblem(*costmap, place, config_.mission.docking.dock);
      boost::asio::post(io_.context(), [this, r, reply, place, made, problem, check_name_free] {
        reply(Respond(r, [&]() -> Response {
          if (problem)
            throw ApiError(http::status::unprocessable_entity, "Place unreachable", *problem, "goal_occupied");
          check_name_free(place);  // again: another request may have taken the name meanwhile
          store_.PutPlace(maps_.active()->name, place);
          Response res = JsonResponse(r, PlaceJson(place, config_.mission.docking.dock),
                                      made ? http::status::created : http::status::ok);
          if (made) res.set(http::field::location, "/api/v1/places/" + place.id);
          return res;
        }));
      });
    });
  };
  routes.Add(http::verb::post, "/api/v1/places", Access::kAdmin,
             [put_place](const Request& r, const Params&, Reply reply) {
               put_place(r, std::move(reply), ParsePlace(ParseJsonBody(r), NewId()), true);
             });
  const auto find_place = [this](const std::string& id) {
    for (const nav::Place& p : store_.Places(maps_.active()->name)) {
      if (p.id == id) return p;
    }
    throw ApiError(http::status::not_found, "Not found", "no place " + id);
  };
  routes.Add(http::verb::get, "/api/v1/places/{id}", Access::kViewer,
             Sync([this, find_place](const Request& r, const Params& p) {
               return JsonResponse(r, PlaceJson(find_place(p.at("id")), config_.mission.docking.dock));
             }));
  routes.Add(http::verb::put, "/api/v1/places/{id}", Access::kAdmin,
             [find_place, put_place](const Request& r, const Params& p, Reply reply) {
               find_place(p.at("id"));
               put_place(r, std::move(reply), ParsePlace(ParseJsonBody(r), p.at("id")), false);
             });
  routes.Add(http::verb::delete_, "/api/v1/places/{id}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               if (!store_.DeletePlace(maps_.active()->name, p.at("id"))) {
                 throw ApiError(http::status::not_found, "Not found", "no place " + p.at("id"));
               }
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));
}

}  // namespace corridor::server
