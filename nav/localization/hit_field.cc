#include "nav/localization/hit_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {

HitField::HitField(const HitFieldOptions& options) : options_(options) {
  if (!(options.resolution_m > 0.0) || !(options.sigma_m > 0.0)) {
    throw std::invalid_argument("HitField: resolution and sigma must be positive");
  }
}

HitField HitField::FromOccupancyGrid(const OccupancyGrid& map, const HitFieldOptions& options) {
  if (map.origin().yaw_rad != 0.0) throw std::invalid_argument("HitField: a map with a rotated origin");
  HitFieldOptions o = options;
  o.resolution_m = map.resolution_m();
  HitField field(o);
  field.width_ = map.width();
  field.height_ = map.height();
  field.min_corner_ = map.origin().translation();
  field.match_.assign(map.cells().size(), 0.0f);
  for (int y = 0; y < field.height_; ++y) {
    for (int x = 0; x < field.width_; ++x) {
      if (map.at({x, y}) >= 65) {
        field.AddHit(field.min_corner_ + (Eigen::Vector2d(x, y).array() + 0.5).matrix() * o.resolution_m);
      }
    }
  }
  return field;
}

CellIndex HitField::CellOf(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d c = (point - min_corner_) / options_.resolution_m;
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

void HitField::GrowToInclude(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const double r = options_.resolution_m;
  const Eigen::Vector2d max_corner = min_corner_ + Eigen::Vector2d(width_, height_) * r;
  // Each hit's reach, and two cells beyond it: bicubic interpolation reads the edge cells past what it evaluates.
  const double border = 2.0 * r + 2.5 * options_.sigma_m;
  if (!empty() && (lo.array() - border >= min_corner_.array()).all() &&
      (hi.array() + border <= max_corner.array()).all()) {
    return;
  }
  const double margin = options_.grow_margin_m;
  Eigen::Vector2d new_min = lo.array() - margin;
  Eigen::Vector2d new_max = hi.array() + margin;
  if (!empty()) {
    new_min = new_min.cwiseMin(min_corner_);
    new_max = new_max.cwiseMax(max_corner);
  }
  // Keep cell boundaries where they were: the new corner is the old one moved by whole cells.
  const Eigen::Vector2d shift_cells = ((min_corner_ - new_min) / r).array().ceil();
  new_min = min_corner_ - shift_cells * r;
  const int new_width = static_cast<int>(std::ceil((new_max.x() - new_min.x()) / r));
  const int new_height = static_cast<int>(std::ceil((new_max.y() - new_min.y()) / r));
  std::vector<float> match(static_cast<std::size_t>(new_width) * new_height, 0.0f);
  const int dx = static_cast<int>(shift_cells.x());
  const int dy = static_cast<int>(shift_cells.y());
  for (int y = 0; y < height_; ++y) {
    std::copy_n(match_.begin() + static_cast<std::size_t>(y) * width_, width_,
                match.begin() + static_cast<std::size_t>(y + dy) * new_width + dx);
  }
  match_ = std::move(match);
  width_ = new_width;
  height_ = new_height;
  min_corner_ = new_min;
}

void HitField::AddHit(const Eigen::Vector2d& hit) {
  const double r = options_.resolution_m;
  const double sigma = options_.sigma_m;
  const int reach = static_cast<int>(std::ceil(2.5 * sigma / r));
  const CellIndex centre = CellOf(hit);
  for (int y = std::max(0, centre.y - reach); y <= std::min(height_ - 1, centre.y + reach); ++y) {
    for (int x = std::max(0, centre.x - reach); x <= std::min(width_ - 1, centre.x + reach); ++x) {
      const Eigen::Vector2d d = min_corner_ + (Eigen::Vector2d(x, y).array() + 0.5).matrix() * r - hit;
      float& value = match_[static_cast<std::size_t>(y) * width_ + x];
      value = std::max(value, static_cast<float>(std::exp(-d.squaredNorm() / (2.0 * sigma * sigma))));
    }
  }
}

void HitField::Insert(const RangeScan& scan, const Pose2& frame_T_base) {
  if (scan.hits.empty()) return;
  const std::vector<Eigen::Vector2f> hits = TransformPoints(frame_T_base, scan.hits);
  Eigen::Vector2d lo = hits.front().cast<double>();
  Eigen::Vector2d hi = lo;
  for (const Eigen::Vector2f& p : hits) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  GrowToInclude(lo, hi);
  for (const Eigen::Vector2f& p : hits) AddHit(p.cast<double>());
}

}  // namespace corridor::nav
