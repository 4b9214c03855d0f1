#include "nav/ground/depth_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {

DepthScan::DepthScan(const PinholeCamera& camera, const DepthScanOptions& options)
    : camera_(camera), options_(options) {
  if (!camera.Valid()) throw std::invalid_argument("DepthScan: the camera needs a positive size and focal length");
  if (options.row_step < 1 || !(options.max_height_m > options.min_height_m) ||
      !(options.max_range_m > options.min_range_m) || !(options.average_within_m >= 0.0)) {
    throw std::invalid_argument(
        "DepthScan: need row_step >= 1, min_height_m < max_height_m, min_range_m < max_range_m, average_within_m >= 0");
  }
  rays_ = BaseFrameRays(camera, options.row_step);
  nearest_.resize(static_cast<std::size_t>(camera.width));
  at_.resize(static_cast<std::size_t>(camera.width));
  count_.resize(static_cast<std::size_t>(camera.width));
  // The optical axis and the rays of the image's first and last columns, flattened onto the floor: a tilted camera's
  // columns lean, so the view is as wide as the narrowest of the rows read.
  const Eigen::Vector2d axis = (camera.base_T_camera.linear() * Eigen::Vector3d::UnitZ()).head<2>();
  const Eigen::Vector3d origin = camera.base_T_camera.translation();
  base_T_view_ = {origin.x(), origin.y(), std::atan2(axis.y(), axis.x())};
  const auto angle_to_axis = [&](const Eigen::Vector3f& ray) {
    const Eigen::Vector2d v = ray.head<2>().cast<double>();
    return std::abs(std::atan2(axis.x() * v.y() - axis.y() * v.x(), axis.dot(v)));
  };
  half_angle_rad_ = std::numbers::pi;
  const auto width = static_cast<std::size_t>(camera.width);
  // A column's direction on the floor, from its middle row read.
  const std::size_t middle = (rays_.size() / width / 2) * width;
  for (std::size_t u = 0; u < width; ++u) {
    const Eigen::Vector2d direction = rays_[middle + u].head<2>().cast<double>().normalized();
    column_end_.push_back(origin.head<2>() + options.max_range_m * direction);
  }
  for (std::size_t first = 0; first < rays_.size(); first += width) {
    half_angle_rad_ = std::min({half_angle_rad_, angle_to_axis(rays_[first]), angle_to_axis(rays_[first + width - 1])});
  }
}

const std::vector<Eigen::Vector2d>& DepthScan::Process(const cv::Mat& depth) {
  if (depth.type() != CV_16UC1 || depth.cols != camera_.width || depth.rows != camera_.height) {
    throw std::invalid_argument("DepthScan: expected a CV_16UC1 depth image of the camera's size");
  }
  const Eigen::Vector3f origin = camera_.base_T_camera.translation().cast<float>();
  const auto low = static_cast<float>(options_.min_height_m);
  const auto high = static_cast<float>(options_.max_height_m);
  const auto min_d = static_cast<float>(options_.min_range_m);
  const auto max_d = static_cast<float>(options_.max_range_m);
  std::fill(nearest_.begin(), nearest_.end(), std::numeric_limits<float>::infinity());
  // Every read pixel between the heights and ranges, with its column and point in the base frame.
  const auto for_each_point = [&](const auto& visit) {
    const Eigen::Vector3f* ray = rays_.data();
    for (int v = 0; v < depth.rows; v += options_.row_step) {
      const auto* row = depth.ptr<std::uint16_t>(v);
      for (int u = 0; u < depth.cols; ++u, ++ray) {
        const float d = static_cast<float>(row[u]) * 0.001f;
        if (d < min_d || d > max_d) continue;  // also holes (0)
        const Eigen::Vector3f p = origin + *ray * d;
        if (p.z() < low || p.z() > high) continue;
        visit(static_cast<std::size_t>(u), p.head<2>());
      }
    }
  };
  for_each_point([&](std::size_t u, const Eigen::Vector2f& p) {
    const float range2 = p.squaredNorm();
    if (range2 < nearest_[u]) {
      nearest_[u] = range2;
      at_[u] = p;
    }
  });
  if (options_.average_within_m > 0.0) {
    // A second pass: the mean of what lies within the band beyond each column's nearest.
    const auto band = static_cast<float>(options_.average_within_m);
    std::vector<float> limit2(nearest_.size());
    for (std::size_t u = 0; u < nearest_.size(); ++u) {
      const float r = std::sqrt(nearest_[u]);
      limit2[u] = (r + band) * (r + band);
      at_[u] = Eigen::Vector2f::Zero();
    }
    std::fill(count_.begin(), count_.end(), 0);
    for_each_point([&](std::size_t u, const Eigen::Vector2f& p) {
      if (p.squaredNorm() > limit2[u]) return;
      at_[u] += p;
      ++count_[u];
    });
    for (std::size_t u = 0; u < nearest_.size(); ++u) {
      if (count_[u] > 0) at_[u] /= static_cast<float>(count_[u]);
    }
  }
  points_.clear();
  misses_.clear();
  for (std::size_t u = 0; u < nearest_.size(); ++u) {
    if (nearest_[u] < std::numeric_limits<float>::infinity()) {
      points_.push_back(at_[u].cast<double>());
    } else {
      misses_.push_back(column_end_[u]);
    }
  }
  if (options_.segment_gap_m > 0.0 && !points_.empty()) {
    // The first and last columns must have a point for a run to touch a side; a hole there means nothing is cut.
    const auto touching = [&](std::size_t column) { return nearest_[column] < std::numeric_limits<float>::infinity(); };
    const auto joined = [&](std::size_t a, std::size_t b) {
      return (points_[a] - points_[b]).norm() <= options_.segment_gap_m;
    };
    std::size_t begin = 0;
    std::size_t end = points_.size();
    if (touching(0)) {
      while (begin + 1 < end && joined(begin, begin + 1)) ++begin;
      ++begin;
    }
    if (touching(nearest_.size() - 1) && end > begin) {
      while (end - 1 > begin && joined(end - 1, end - 2)) --end;
      --end;
    }
    points_.erase(points_.begin() + static_cast<std::ptrdiff_t>(end), points_.end());
    points_.erase(points_.begin(), points_.begin() + static_cast<std::ptrdiff_t>(begin));
  }
  return points_;
}

}  // namespace corridor::nav
