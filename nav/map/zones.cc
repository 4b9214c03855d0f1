#include "nav/map/zones.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace corridor::nav {

const char* ToString(ZoneKind kind) { return kind == ZoneKind::kKeepOut ? "keep_out" : "speed_limit"; }

std::optional<ZoneKind> ZoneKindFromString(const std::string& text) {
  if (text == "keep_out") return ZoneKind::kKeepOut;
  if (text == "speed_limit") return ZoneKind::kSpeedLimit;
  return std::nullopt;
}

const char* ToString(PlaceKind kind) { return kind == PlaceKind::kDock ? "dock" : "place"; }

std::optional<PlaceKind> PlaceKindFromString(const std::string& text) {
  if (text == "place") return PlaceKind::kPlace;
  if (text == "dock") return PlaceKind::kDock;
  return std::nullopt;
}

void Validate(const Zone& zone) {
  if (zone.polygon.size() < 3) throw InvalidZone("polygon: needs at least 3 vertices");
  double twice_area = 0.0;
  for (std::size_t i = 0; i < zone.polygon.size(); ++i) {
    const Eigen::Vector2d& a = zone.polygon[i];
    const Eigen::Vector2d& b = zone.polygon[(i + 1) % zone.polygon.size()];
    if (!a.allFinite()) throw InvalidZone("polygon: vertex " + std::to_string(i) + " is not a finite point");
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  if (std::abs(twice_area) < 1e-6) throw InvalidZone("polygon: has no area");
  if (zone.kind == ZoneKind::kSpeedLimit && !(zone.max_speed_mps > 0.0 && std::isfinite(zone.max_speed_mps))) {
    throw InvalidZone("max_speed_mps: must be a positive number for a speed_limit zone");
  }
}

bool Contains(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

void Rasterize(const std::vector<Eigen::Vector2d>& polygon, const OccupancyGrid& grid, std::vector<std::uint8_t>& mask,
               std::uint8_t value) {
  // Cell (x, y) of the grid is pixel (x, y) of this image (row y), so the image is the grid upside down: no
  // flip is needed because nothing here is displayed.
  cv::Mat image(grid.height(), grid.width(), CV_8UC1, mask.data());
  constexpr int kShift = 8;
  std::vector<cv::Point> pixels;
  const Pose2 map_T_grid = grid.origin().Inverse();
  for (const Eigen::Vector2d& v : polygon) {
    // Pixel centres sit at integer coordinates for OpenCV; cell centres are at (x + 0.5) * resolution.
    const Eigen::Vector2d c = map_T_grid.Transform(v) / grid.resolution_m() - Eigen::Vector2d(0.5, 0.5);
    pixels.emplace_back(static_cast<int>(std::lround(c.x() * (1 << kShift))),
                        static_cast<int>(std::lround(c.y() * (1 << kShift))));
  }
  const std::vector<std::vector<cv::Point>> polygons{pixels};
  cv::fillPoly(image, polygons, cv::Scalar(value), cv::LINE_8, kShift);
  cv::polylines(image, polygons, true, cv::Scalar(value), 1, cv::LINE_8, kShift);
}

}  // namespace corridor::nav
