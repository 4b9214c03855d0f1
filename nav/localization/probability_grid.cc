#include "nav/localization/probability_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nav/map/grid_ray.h"

namespace corridor::nav {
namespace {

float Odds(double p) { return static_cast<float>(p / (1.0 - p)); }
float FromOdds(float odds) { return odds / (1.0f + odds); }

}  // namespace

ProbabilityGrid::ProbabilityGrid(const ProbabilityGridOptions& options)
    : options_(options), hit_odds_(Odds(options.hit_probability)), miss_odds_(Odds(options.miss_probability)) {
  const auto in_unit = [](double p) { return p > 0.0 && p < 1.0; };
  if (!in_unit(options.hit_probability) || !in_unit(options.miss_probability) || !in_unit(options.min_probability) ||
      !in_unit(options.max_probability) || options.min_probability >= options.max_probability) {
    throw std::invalid_argument("ProbabilityGrid: probabilities must lie in (0, 1) with min < max");
  }
  if (!(options.resolution_m > 0.0)) throw std::invalid_argument("ProbabilityGrid: resolution must be positive");
}

ProbabilityGrid ProbabilityGrid::FromOccupancyGrid(const OccupancyGrid& map, const ProbabilityGridOptions& options) {
  if (map.origin().yaw_rad != 0.0) throw std::invalid_argument("ProbabilityGrid: a map with a rotated origin");
  ProbabilityGridOptions o = options;
  o.resolution_m = map.resolution_m();
  ProbabilityGrid grid(o);
  grid.width_ = map.width();
  grid.height_ = map.height();
  grid.min_corner_ = map.origin().translation();
  const std::size_t n = map.cells().size();
  grid.probability_.assign(n, grid.unknown_probability());
  grid.known_.assign(n, 0);
  grid.stamp_.assign(n, 0);
  grid.match_.assign(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int8_t v = map.cells()[i];
    if (v == kUnknownCell) continue;
    grid.known_[i] = 1;
    grid.probability_[i] = static_cast<float>(v >= 65 ? o.max_probability : o.min_probability);
  }
  for (int y = 0; y < grid.height_; ++y) {
    for (int x = 0; x < grid.width_; ++x) {
      if (map.at({x, y}) >= 65) grid.AddToField(grid.min_corner_ + (Eigen::Vector2d(x, y).array() + 0.5).matrix() * o.resolution_m);
    }
  }
  return grid;
}

CellIndex ProbabilityGrid::CellOf(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d c = (point - min_corner_) / options_.resolution_m;
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

void ProbabilityGrid::GrowToInclude(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const double r = options_.resolution_m;
  const Eigen::Vector2d max_corner = min_corner_ + Eigen::Vector2d(width_, height_) * r;
  // Two cells of unknown always border what was inserted: bicubic interpolation reads the edge cells beyond.
  const double border = 2.0 * r + 2.5 * options_.match_sigma_m;
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
  const std::size_t n = static_cast<std::size_t>(new_width) * new_height;
  std::vector<float> probability(n, unknown_probability());
  std::vector<std::uint8_t> known(n, 0);
  std::vector<std::uint32_t> stamp(n, 0);
  std::vector<float> match(n, 0.0f);
  const int dx = static_cast<int>(shift_cells.x());
  const int dy = static_cast<int>(shift_cells.y());
  for (int y = 0; y < height_; ++y) {
    const std::size_t from = static_cast<std::size_t>(y) * width_;
    const std::size_t to = static_cast<std::size_t>(y + dy) * new_width + dx;
    std::copy_n(probability_.begin() + from, width_, probability.begin() + to);
    std::copy_n(known_.begin() + from, width_, known.begin() + to);
    std::copy_n(stamp_.begin() + from, width_, stamp.begin() + to);
    std::copy_n(match_.begin() + from, width_, match.begin() + to);
  }
  probability_ = std::move(probability);
  known_ = std::move(known);
  stamp_ = std::move(stamp);
  match_ = std::move(match);
  width_ = new_width;
  height_ = new_height;
  min_corner_ = new_min;
}

void ProbabilityGrid::Update(CellIndex cell, float odds_factor, float first_value) {
  const std::size_t i = static_cast<std::size_t>(cell.y) * width_ + cell.x;
  if (stamp_[i] == insertion_) return;
  stamp_[i] = insertion_;
  if (!known_[i]) {
    known_[i] = 1;
    probability_[i] = first_value;
    return;
  }
  const float p = probability_[i];
  probability_[i] = std::clamp(FromOdds(p / (1.0f - p) * odds_factor), static_cast<float>(options_.min_probability),
                               static_cast<float>(options_.max_probability));
}

void ProbabilityGrid::AddToField(const Eigen::Vector2d& hit) {
  const double r = options_.resolution_m;
  const double sigma = options_.match_sigma_m;
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

void ProbabilityGrid::Insert(const RangeScan& scan, const Pose2& frame_T_base) {
  const std::vector<Eigen::Vector2f> hits = TransformPoints(frame_T_base, scan.hits);
  const std::vector<Eigen::Vector2f> misses = TransformPoints(frame_T_base, scan.misses);
  const Eigen::Vector2d origin = frame_T_base.Transform(scan.origin.cast<double>());
  Eigen::Vector2d lo = origin;
  Eigen::Vector2d hi = origin;
  for (const auto* points : {&hits, &misses}) {
    for (const Eigen::Vector2f& p : *points) {
      lo = lo.cwiseMin(p.cast<double>());
      hi = hi.cwiseMax(p.cast<double>());
    }
  }
  GrowToInclude(lo, hi);
  ++insertion_;
  const auto p_hit = static_cast<float>(options_.hit_probability);
  const auto p_miss = static_cast<float>(options_.miss_probability);
  // Hits first: a cell that a beam ends in is not cleared by another beam passing through it in the same scan.
  for (const Eigen::Vector2f& p : hits) {
    Update(CellOf(p.cast<double>()), hit_odds_, p_hit);
    AddToField(p.cast<double>());
  }
  const Eigen::Vector2d from = (origin - min_corner_) / options_.resolution_m;
  const auto clear = [&](CellIndex cell) { Update(cell, miss_odds_, p_miss); };
  for (const Eigen::Vector2f& p : hits) {
    ForEachCellBefore(from, (p.cast<double>() - min_corner_) / options_.resolution_m, clear);
  }
  for (const Eigen::Vector2f& p : misses) {
    clear(ForEachCellBefore(from, (p.cast<double>() - min_corner_) / options_.resolution_m, clear));
  }
}

OccupancyGrid ProbabilityGrid::ToOccupancyGrid() const {
  OccupancyGrid out(width_, height_, options_.resolution_m, Pose2{min_corner_.x(), min_corner_.y(), 0.0});
  for (std::size_t i = 0; i < probability_.size(); ++i) {
    if (!known_[i]) continue;
    out.mutable_cells()[i] = probability_[i] > 0.65f ? kOccupiedCell : probability_[i] < 0.196f ? kFreeCell : kUnknownCell;
  }
  return out;
}

}  // namespace corridor::nav
