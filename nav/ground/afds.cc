#include "nav/ground/afds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
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
      const Eigen::Vector3f& ray = rays_[static_cast<std::size_t>(v * camera.width + u)];
      const double floor_depth = ray.z() < 0.0f ? origin.z() / -ray.z() : options.max_range_m;
      region_of_pixel_.push_back(!camera.stereo.Sees(u + 0.5, floor_depth)
                                     ? -1
                                     : v * options.grid_rows / camera.height * options.grid_columns +
                                           u * options.grid_columns / camera.width);
    }
  }
  regions_.resize(static_cast<std::size_t>(options.grid_columns * options.grid_rows));
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
      if (region_of_pixel_[pixel] < 0) continue;
      const Eigen::Vector3d p = origin + rays_[pixel].cast<double>() * d;
      if (p.x() < options_.min_range_m || p.x() > options_.max_range_m) continue;
      points_.push_back({p, region_of_pixel_[pixel]});
      cloud_.push_back(p);
      regions_[static_cast<std::size_t>(region_of_pixel_[pixel])].push_back(p);
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
    region_floor_[r] = FitRegion(regions_[r], cell);
  }

  // 4. Every point's height above its region's floor, and the obstacles among them.
  heights_.resize(points_.size());
  frame_.obstacles.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Point& point = points_[i];
    heights_[i] = static_cast<float>(region_floor_[static_cast<std::size_t>(point.region)].Distance(point.p));
    if (heights_[i] > options_.max_step_m || heights_[i] < -options_.max_drop_m) {
      frame_.obstacles.emplace_back(point.p.x(), point.p.y(), heights_[i]);
    }
  }
  FillLanes(heights_);
  return frame_;
}

Plane Afds::FitRegion(std::vector<Eigen::Vector3d>& points, AfdsCell& cell) {
  cell.points = static_cast<int>(points.size());
  Plane region_floor = frame_.floor;
  if (points.size() < static_cast<std::size_t>(options_.min_plane_points)) return region_floor;
  // The inlier distance at the region's median range: depth noise grows with its square.
  std::vector<double> ranges;
  ranges.reserve(points.size());
  for (const Eigen::Vector3d& p : points) ranges.push_back(p.x());
  std::nth_element(ranges.begin(), ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2), ranges.end());
  const double range = ranges[ranges.size() / 2];
  const double inlier = options_.inlier_m + options_.noise_b_per_m * range * range;
  const double cos_floor = std::cos(Radians(options_.max_floor_angle_deg));

  int floor_support = 0;
  std::vector<Eigen::Vector3d> on_plane;
  for (int k = 0; k < options_.max_planes && points.size() >= static_cast<std::size_t>(options_.min_plane_points);
       ++k) {
    const auto found = RansacPlane(points, {options_.iterations, inlier}, rng_);
    if (!found || found->second < options_.min_plane_points) break;
    const std::optional<Plane> plane = RefinePlane(points, found->first, inlier);
    if (!plane) break;
    // Its points out of the region's, their heights above the frame's floor.
    on_plane.clear();
    std::erase_if(points, [&](const Eigen::Vector3d& p) {
      if (std::abs(plane->Distance(p)) >= inlier) return false;
      on_plane.push_back(p);
      return true;
    });
    if (on_plane.size() < static_cast<std::size_t>(options_.min_plane_points)) break;
    ++cell.planes;
    double sum = 0.0;
    double top = -std::numeric_limits<double>::infinity();
    double nearest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : on_plane) {
      const double h = frame_.floor.Distance(p);
      sum += h;
      top = std::max(top, h);
      nearest = std::min(nearest, p.x());
    }
    const double mean = sum / static_cast<double>(on_plane.size());
    const bool horizontal = std::abs(plane->normal.dot(frame_.floor.normal)) >= cos_floor;
    if (horizontal && std::abs(mean) <= options_.floor_tolerance_m) {
      if (static_cast<int>(on_plane.size()) > floor_support) {  // the region's floor: its best-supported one
        floor_support = static_cast<int>(on_plane.size());
        region_floor = *plane;
        if (region_floor.normal.dot(frame_.floor.normal) < 0.0) region_floor = {-plane->normal, -plane->offset};
        cell.own_floor = true;
        cell.floor_height_m = mean;
      }
      continue;
    }
    // An obstacle: a top at its mean height, a face at its highest point and half a sampled row (the edge lies
    // between that row and the next one up, which missed it).
    const double height = horizontal ? mean : top + 0.5 * nearest * options_.stride_px / camera_.fy;
    if (height > options_.max_step_m && height > cell.obstacle_height_m) {
      cell.obstacle_height_m = height;
      cell.obstacle_range_m = nearest;
    }
  }
  // Heights in the cell are above its own floor.
  if (cell.own_floor && cell.obstacle_height_m > 0.0) cell.obstacle_height_m -= cell.floor_height_m;
  return region_floor;
}

void Afds::FillLanes(const std::vector<float>& heights) {
  // Per lane, its points' forward distances and heights, nearest first.
  for (auto& lane : lane_points_) lane.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d& p = points_[i].p;
    if (p.x() > lane_options_.max_range_m) continue;
    const int j = LaneOnLine(lane_options_, lane_count(), p.y());
    if (j >= 0) lane_points_[static_cast<std::size_t>(j)].emplace_back(static_cast<float>(p.x()), heights[i]);
  }
  const auto obstacle = [&](float height) { return height > options_.max_step_m || height < -options_.max_drop_m; };
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
      if (!obstacle(height)) {
        last_floor = x;
        continue;
      }
      for (std::size_t n = k + 1; n < points.size() && points[n].first - x <= options_.obstacle_run_m; ++n) {
        if (!obstacle(points[n].second)) continue;
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
