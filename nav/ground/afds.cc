#include "nav/ground/afds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace corridor::nav {
namespace {

double Radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

}  // namespace

Afds::Afds(const PinholeCamera& camera, const AfdsOptions& options, const MorpOptions& lanes)
    : camera_(camera), options_(options), lane_options_(lanes), rng_(options.seed) {
  if (!camera.Valid()) throw std::invalid_argument("AFDS: the camera needs a positive size and focal length");
  if (options.grid_columns < 1 || options.grid_columns > 32 || options.grid_rows < 1 || options.grid_rows > 32) {
    throw std::invalid_argument("AFDS: the region grid must be 1 x 1 to 32 x 32, not " +
                                std::to_string(options.grid_columns) + " x " + std::to_string(options.grid_rows));
  }
  if (options.stride_px < 1 || !(options.max_range_m > options.min_range_m) || !(options.inlier_m > 0.0) ||
      options.iterations < 1 || options.min_plane_points < 3 || options.max_planes < 1) {
    throw std::invalid_argument(
        "AFDS: stride, iterations, plane sizes and inlier distance must be positive and "
        "max_range_m above min_range_m");
  }
  if (!(lanes.span_m > 0.0) || !(lanes.lane_width_m > 0.0)) {
    throw std::invalid_argument("AFDS: the lanes' widths must be positive");
  }
  lane_offsets_ = LaneOffsets(lanes);
  for (const double offset : lane_offsets_) lane_blind_m_.push_back(LaneBlindRange(camera, lanes, offset));
  rays_ = BaseFrameRays(camera);
  // A pixel whose ray meets the floor (or, above the horizon, max_range_m) where only the left camera sees it has no
  // true depth, and nothing nearer on its ray has one either.
  const Eigen::Vector3d origin = camera.base_T_camera.translation();
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3f& ray =
          rays_[static_cast<std::size_t>(v) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(u)];
      const double floor_depth = ray.z() < 0.0f ? origin.z() / -ray.z() : options.max_range_m;
      region_of_pixel_.push_back(!camera.stereo.Sees(u + 0.5, floor_depth)
                                     ? -1
                                     : v * options.grid_rows / camera.height * options.grid_columns +
                                           u * options.grid_columns / camera.width);
    }
  }
  regions_.resize(static_cast<std::size_t>(options.grid_columns) * static_cast<std::size_t>(options.grid_rows));
  region_floor_.resize(regions_.size());
  frame_.cells.resize(regions_.size());
  frame_.lanes.resize(lane_offsets_.size());
  lane_points_.resize(lane_offsets_.size());
}

const AfdsFrame& Afds::Process(const cv::Mat& depth) {
  const bool millimetres = depth.type() == CV_16UC1;
  if ((!millimetres && depth.type() != CV_32FC1) || depth.cols != camera_.width || depth.rows != camera_.height) {
    throw std::invalid_argument("AFDS: expected a " + std::to_string(camera_.width) + "x" +
                                std::to_string(camera_.height) + " depth image, CV_16UC1 (mm) or CV_32FC1 (m)");
  }
  // The points, base frame.
  const Eigen::Vector3d origin = camera_.base_T_camera.translation();
  points_.clear();
  cloud_.clear();
  for (auto& region : regions_) region.clear();
  for (int v = 0; v < depth.rows; v += options_.stride_px) {
    for (int u = 0; u < depth.cols; u += options_.stride_px) {
      const double d = millimetres ? depth.ptr<std::uint16_t>(v)[u] * 0.001 : depth.ptr<float>(v)[u];
      if (!(d > 0.0) || !std::isfinite(d)) continue;
      const std::size_t pixel = static_cast<std::size_t>(v) * static_cast<std::size_t>(depth.cols) + u;
      const int region = region_of_pixel_[pixel];
      if (region < 0) continue;
      const Eigen::Vector3d p = origin + rays_[pixel].cast<double>() * d;
      if (p.x() < options_.min_range_m || p.x() > options_.max_range_m) continue;
      regions_[static_cast<std::size_t>(region)].push_back(static_cast<int>(points_.size()));
      points_.push_back({p, region, u, v});
      cloud_.push_back(p);
    }
  }

  // 1. The frame's floor: horizontal, near the mounting's floor, the most support.
  const double cos_floor = std::cos(Radians(options_.max_floor_angle_deg));
  const auto floor_like = [&](Plane& plane) {
    if (plane.normal.z() < 0.0) plane = {-plane.normal, -plane.offset};
    return plane.normal.z() >= cos_floor && std::abs(plane.offset) <= options_.floor_search_m;
  };
  frame_.floor = Plane{Eigen::Vector3d::UnitZ(), 0.0};
  frame_.floor_found = false;
  const auto floor = RansacPlane(cloud_, {options_.iterations * 2, options_.inlier_m}, rng_, floor_like);
  if (floor && floor->second >= options_.min_plane_points) {
    if (const auto refined = RefinePlane(cloud_, floor->first, options_.inlier_m)) {
      frame_.floor = *refined;
      frame_.floor_found = true;
    }
  }

  // 2 and 3, region by region.
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    AfdsCell& cell = frame_.cells[r];
    cell = AfdsCell{};
    cell.column = static_cast<int>(r) % options_.grid_columns;
    cell.row = static_cast<int>(r) / options_.grid_columns;
    region_floor_[r] = FitRegion(regions_[r], cell, depth);
  }

  // 4. Every point's height above its region's floor, and the obstacles among them.
  heights_.resize(points_.size());
  frame_.obstacles.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Point& point = points_[i];
    heights_[i] = static_cast<float>(region_floor_[static_cast<std::size_t>(point.region)].Distance(point.p));
    if (Obstacle(heights_[i])) frame_.obstacles.emplace_back(point.p.x(), point.p.y(), heights_[i]);
  }
  FillLanes();
  return frame_;
}

Plane Afds::FitRegion(std::vector<int>& members, AfdsCell& cell, const cv::Mat& depth) {
  cell.points = static_cast<int>(members.size());
  Plane region_floor = frame_.floor;
  const auto enough = [&] { return members.size() >= static_cast<std::size_t>(options_.min_plane_points); };
  if (!enough()) return region_floor;
  const auto positions = [&] {
    positions_.clear();
    for (const int i : members) positions_.push_back(points_[static_cast<std::size_t>(i)].p);
    return std::span<const Eigen::Vector3d>(positions_);
  };
  // Takes the members within `inlier` of `plane` out into on_plane_; their mean height above the frame's floor.
  const auto take = [&](const Plane& plane, double inlier) {
    on_plane_.clear();
    double sum = 0.0;
    std::erase_if(members, [&](int i) {
      const Eigen::Vector3d& p = points_[static_cast<std::size_t>(i)].p;
      if (std::abs(plane.Distance(p)) >= inlier) return false;
      on_plane_.push_back(i);
      sum += frame_.floor.Distance(p);
      return true;
    });
    return on_plane_.empty() ? 0.0 : sum / static_cast<double>(on_plane_.size());
  };
  const double cos_floor = std::cos(Radians(options_.max_floor_angle_deg));
  const auto horizontal = [&](const Plane& plane) {
    return std::abs(plane.normal.dot(frame_.floor.normal)) >= cos_floor;
  };

  // 2a. The region's own floor first, at the floor's own inlier distance: a low camera sees the floor at a grazing
  // angle, so the depth noise (along the rays) moves its points little up or down.
  std::span<const Eigen::Vector3d> points = positions();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  const auto floor_like = [&](Plane& plane) {
    if (plane.normal.dot(frame_.floor.normal) < 0.0) plane = {-plane.normal, -plane.offset};
    const Eigen::Vector3d on = centroid - plane.normal * plane.Distance(centroid);  // the plane under the centroid
    return horizontal(plane) && std::abs(frame_.floor.Distance(on)) <= options_.floor_tolerance_m;
  };
  if (const auto found = RansacPlane(points, {options_.iterations, options_.inlier_m}, rng_, floor_like);
      found && found->second >= options_.min_plane_points) {
    if (const std::optional<Plane> plane = RefinePlane(points, found->first, options_.inlier_m)) {
      const double mean = take(*plane, options_.inlier_m);
      if (on_plane_.size() >= static_cast<std::size_t>(options_.min_plane_points)) {
        region_floor = *plane;
        if (region_floor.normal.dot(frame_.floor.normal) < 0.0) region_floor = {-plane->normal, -plane->offset};
        cell.own_floor = true;
        cell.floor_height_m = mean;
        ++cell.planes;
      }
    }
  }

  // 2b. The planes on it, in turn, at an inlier distance that grows with the region's range as depth noise does (a
  // face seen head-on has its noise across it).
  if (!enough()) return region_floor;
  std::vector<double> ranges;
  for (const int i : members) ranges.push_back(points_[static_cast<std::size_t>(i)].p.x());
  std::nth_element(ranges.begin(), ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2), ranges.end());
  const double range = ranges[ranges.size() / 2];
  const double inlier = options_.inlier_m + options_.noise_b_per_m * range * range;
  for (int k = 0; k < options_.max_planes && enough(); ++k) {
    points = positions();
    const auto found = RansacPlane(points, {options_.iterations, inlier}, rng_);
    if (!found || found->second < options_.min_plane_points) break;
    const std::optional<Plane> plane = RefinePlane(points, found->first, inlier);
    if (!plane) break;
    const double mean = take(*plane, inlier);
    if (on_plane_.size() < static_cast<std::size_t>(options_.min_plane_points)) break;
    ++cell.planes;
    if (horizontal(*plane) && std::abs(mean) <= options_.floor_tolerance_m) continue;  // more floor
    // An obstacle: a top at its mean height, a face at its highest point.
    const double height = horizontal(*plane) ? mean : FaceTop(on_plane_, *plane, depth);
    if (height > options_.max_step_m && height > cell.obstacle_height_m) {
      cell.obstacle_height_m = height;
      cell.obstacle_range_m = std::numeric_limits<double>::infinity();
      for (const int i : on_plane_) {
        cell.obstacle_range_m = std::min(cell.obstacle_range_m, points_[static_cast<std::size_t>(i)].p.x());
      }
    }
  }
  // Heights in the cell are above its own floor.
  if (cell.own_floor && cell.obstacle_height_m > 0.0) cell.obstacle_height_m -= cell.floor_height_m;
  return region_floor;
}

double Afds::FaceTop(const std::vector<int>& face, const Plane& plane, const cv::Mat& depth) const {
  const Point* top = nullptr;
  double top_height = -std::numeric_limits<double>::infinity();
  for (const int i : face) {
    const Point& point = points_[static_cast<std::size_t>(i)];
    const double h = frame_.floor.Distance(point.p);
    if (h > top_height) {
      top_height = h;
      top = &point;
    }
  }
  // Up the image from the highest point, pixel by pixel (not every stride-th), while the face goes on.
  const Eigen::Vector3d origin = camera_.base_T_camera.translation();
  const bool millimetres = depth.type() == CV_16UC1;
  const auto at = [&](int v) -> std::optional<Eigen::Vector3d> {
    if (v < 0) return std::nullopt;
    const double d = millimetres ? depth.ptr<std::uint16_t>(v)[top->u] * 0.001 : depth.ptr<float>(v)[top->u];
    if (!(d > 0.0) || !std::isfinite(d)) return std::nullopt;
    return origin + rays_[static_cast<std::size_t>(v) * static_cast<std::size_t>(camera_.width) +
                          static_cast<std::size_t>(top->u)]
                            .cast<double>() *
                        d;
  };
  const double inlier = options_.inlier_m + options_.noise_b_per_m * top->p.x() * top->p.x();
  Eigen::Vector3d edge = top->p;
  int v = top->v - 1;
  for (; v >= top->v - 4 * options_.stride_px; --v) {
    const std::optional<Eigen::Vector3d> p = at(v);
    if (!p || std::abs(plane.Distance(*p)) >= inlier) break;
    edge = *p;
  }
  top_height = frame_.floor.Distance(edge);
  // The pixel above it at the same height (within a quarter of a pixel row's height on an upright face): a level top
  // the camera sees (a box lower than it), and the face's top is the obstacle's height. Else the face hides what lies
  // behind it, and its edge lies between that pixel row and the next one up, which missed it: half a row up on
  // average, in height along the plane (a row's whole height on an upright face, none on a level one).
  if (const std::optional<Eigen::Vector3d> above = at(v)) {
    if (std::abs(frame_.floor.Distance(*above) - top_height) <= 0.25 * edge.x() / camera_.fy) return top_height;
  }
  // The ray to the edge turned up by an angle a moves its meeting with the plane up by t (up . (r' - r (n . r') /
  // (n . r))) a, with r the ray's direction, r' its turn (r turned up a right angle) and t the distance.
  const Eigen::Vector3d ray = edge - origin;
  const double t = ray.norm();
  const Eigen::Vector3d r = ray / t;
  const Eigen::Vector3d& up = frame_.floor.normal;
  const Eigen::Vector3d across = r - up * r.dot(up);
  if (across.norm() < 1e-6 || std::abs(plane.normal.dot(r)) < 1e-3) return top_height;
  const Eigen::Vector3d turned = up * across.norm() - across.normalized() * r.dot(up);
  const double rise_per_rad = t * (up.dot(turned) - up.dot(r) * plane.normal.dot(turned) / plane.normal.dot(r));
  return top_height + std::clamp(rise_per_rad, 0.0, t) * 0.5 / camera_.fy;
}

void Afds::FillLanes() {
  // Per lane, its points' forward distances and heights, nearest first.
  for (auto& lane : lane_points_) lane.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d& p = points_[i].p;
    if (p.x() > lane_options_.max_range_m) continue;
    const int j = LaneOnLine(lane_options_, lane_count(), p.y());
    if (j >= 0) lane_points_[static_cast<std::size_t>(j)].emplace_back(static_cast<float>(p.x()), heights_[i]);
  }
  for (std::size_t j = 0; j < frame_.lanes.size(); ++j) {
    LaneResult& out = frame_.lanes[j];
    out = LaneResult{};
    out.offset_m = lane_offsets_[j];
    std::vector<std::pair<float, float>>& points = lane_points_[j];
    std::sort(points.begin(), points.end());
    if (points.empty() || points.front().first > lane_blind_m_[j]) {  // nothing seen near the robot: blind, stop
      out.blind = true;
      out.dead_end = true;
      out.free_distance_m = lane_options_.min_range_m;
      continue;
    }
    float last_floor = 0.0f;
    for (std::size_t k = 0; k < points.size() && !out.dead_end; ++k) {
      const auto [x, height] = points[k];
      if (!Obstacle(height)) {
        last_floor = x;
        continue;
      }
      for (std::size_t n = k + 1; n < points.size() && points[n].first - x <= options_.obstacle_run_m; ++n) {
        if (!Obstacle(points[n].second)) continue;
        // A rise stands where it starts; beyond a drop's edge the lower floor is first seen much farther out, so
        // the lane is free up to the last floor point, the edge.
        out.dead_end = true;
        out.free_distance_m = height > 0.0f || last_floor == 0.0f ? x : std::min(x, last_floor);
        out.point = {x, out.offset_m, height};
        break;
      }
    }
    if (!out.dead_end) out.free_distance_m = std::min(lane_options_.max_range_m, static_cast<double>(last_floor));
  }
}

}  // namespace corridor::nav
