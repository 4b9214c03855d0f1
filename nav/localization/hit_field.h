// What scan matching matches against: a likelihood field of the walls a submap or a map holds. Each cell holds
// exp(-d^2 / (2 sigma^2)) for its centre's distance d to the nearest hit inserted, computed from the hits' exact
// positions, so that walls are located to a fraction of a cell (matching occupancy probabilities, as Cartographer's
// submaps do (Hess et al., ICRA 2016, section IV), puts walls at cell centres: a bias of up to half a cell, 2-4 cm
// measured on constructed scans). The field grows to hold what is inserted. Free space is not kept: the map the robot
// shows is rendered separately (RenderScans, nav/localization/graph_slam.h).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/localization/range_scan.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct HitFieldOptions {
  double resolution_m = 0.05;
  double sigma_m = 0.05;       // of the likelihood around each hit
  double grow_margin_m = 4.0;  // added around what forces the field to grow, to grow seldom
};

class HitField {
 public:
  // An empty field. Throws std::invalid_argument for a resolution or sigma <= 0.
  explicit HitField(const HitFieldOptions& options = {});
  // The field of a map's occupied cells (each cell's centre a hit), in the map frame, at the map's resolution.
  // Throws std::invalid_argument for a map whose origin is rotated.
  static HitField FromOccupancyGrid(const OccupancyGrid& map, const HitFieldOptions& options = {});

  // Inserts a scan's hits, taken with the robot at frame_T_base (the field's frame).
  void Insert(const RangeScan& scan, const Pose2& frame_T_base);

  double resolution_m() const { return options_.resolution_m; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Lower-left corner of cell (0, 0) in the field's frame.
  const Eigen::Vector2d& min_corner() const { return min_corner_; }
  bool empty() const { return width_ == 0; }
  // Row-major values in [0, 1], width() x height().
  const std::vector<float>& match_values() const { return match_; }
  // A cell's value; 0 outside the field.
  float match_value(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
    return match_[static_cast<std::size_t>(y) * width_ + x];
  }
  // The cell that holds a point (not necessarily inside the field).
  CellIndex CellOf(const Eigen::Vector2d& point) const;

 private:
  void GrowToInclude(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);
  void AddHit(const Eigen::Vector2d& hit);

  HitFieldOptions options_;
  int width_ = 0;
  int height_ = 0;
  Eigen::Vector2d min_corner_ = Eigen::Vector2d::Zero();
  std::vector<float> match_;
};

}  // namespace corridor::nav
