// Zones drawn on the map (keep-out areas and speed limits) and named places. Polygons are in the map frame,
// metres, vertices in order (either winding); the even-odd rule decides inside.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

enum class ZoneKind { kKeepOut, kSpeedLimit };

struct Zone {
  std::string id;
  std::string name;
  ZoneKind kind = ZoneKind::kKeepOut;
  std::vector<Eigen::Vector2d> polygon;
  double max_speed_mps = 0.0;  // kSpeedLimit only: the highest speed allowed inside
};

// A named place. A dock's pose is the robot's when it stands on the dock (facing it); missions to a dock end docked
// (nav/mission/docking.h).
enum class PlaceKind { kPlace, kDock };
const char* ToString(PlaceKind kind);
std::optional<PlaceKind> PlaceKindFromString(const std::string& text);

struct Place {
  std::string id;
  std::string name;
  Pose2 pose;
  PlaceKind kind = PlaceKind::kPlace;
};

// A zone or place that cannot be used; what() says which field is wrong.
class InvalidZone : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws InvalidZone: fewer than 3 vertices, non-finite coordinates, zero area, or a speed limit <= 0.
void Validate(const Zone& zone);
const char* ToString(ZoneKind kind);
std::optional<ZoneKind> ZoneKindFromString(const std::string& text);

bool Contains(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& point);

// Marks with `value` every cell of `mask` (row-major, grid-sized) whose centre lies in the polygon, and every cell
// the polygon's outline crosses, so that thin zones are never lost between cell centres.
void Rasterize(const std::vector<Eigen::Vector2d>& polygon, const OccupancyGrid& grid, std::vector<std::uint8_t>& mask,
               std::uint8_t value);

}  // namespace corridor::nav
