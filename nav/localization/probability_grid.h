// A grid of occupancy probabilities that scan matching reads and range scans are inserted into (the submaps of
// Hess, Kohler, Rapp and Andor, "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016, section IV): a hit multiplies
// a cell's odds by odds(hit_probability), a beam passing through by odds(miss_probability), each cell at most once
// per scan. The grid grows to hold what is inserted.
//
// Scan matching does not read the probabilities but a likelihood field of the hits beside them: each cell holds
// exp(-d^2 / (2 sigma^2)) for its centre's distance d to the nearest hit ever inserted, computed from the hits' exact
// positions. Walls are then located to a fraction of a cell (a probability grid puts them at cell centres, which biases
// a match by up to half a cell), and a wall seen from two sides or grazed by later beams keeps its place.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/localization/range_scan.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct ProbabilityGridOptions {
  double resolution_m = 0.05;
  double hit_probability = 0.7;
  double miss_probability = 0.4;
  double min_probability = 0.1;  // observed cells are clamped to [min, max] so that they can still change
  double max_probability = 0.9;
  double grow_margin_m = 4.0;    // added around what forces the grid to grow, to grow seldom
  double match_sigma_m = 0.05;   // of the hits' likelihood field
};

class ProbabilityGrid {
 public:
  // An empty grid. Throws std::invalid_argument for probabilities outside (0, 1), min >= max, or resolution <= 0.
  explicit ProbabilityGrid(const ProbabilityGridOptions& options = {});
  // The map's occupied cells at max_probability, free cells at min_probability, unknown cells unknown, in the map
  // frame; each occupied cell's centre is a hit. Throws std::invalid_argument for a map whose origin is rotated.
  static ProbabilityGrid FromOccupancyGrid(const OccupancyGrid& map, const ProbabilityGridOptions& options = {});

  // Inserts a scan taken with the robot at frame_T_base (the grid's frame).
  void Insert(const RangeScan& scan, const Pose2& frame_T_base);

  double resolution_m() const { return options_.resolution_m; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Lower-left corner of cell (0, 0) in the grid's frame.
  const Eigen::Vector2d& min_corner() const { return min_corner_; }
  bool empty() const { return width_ == 0; }
  float unknown_probability() const { return static_cast<float>(options_.min_probability); }
  // Row-major probabilities, width() x height(); unknown cells hold unknown_probability().
  const std::vector<float>& probabilities() const { return probability_; }
  // The probability of a cell; unknown_probability() outside the grid.
  float probability(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return unknown_probability();
    return probability_[static_cast<std::size_t>(y) * width_ + x];
  }
  // Row-major likelihood field of the hits in [0, 1], what scan matching scores against; 0 outside.
  const std::vector<float>& match_values() const { return match_; }
  float match_value(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
    return match_[static_cast<std::size_t>(y) * width_ + x];
  }
  // The cell that holds a point (not necessarily inside the grid).
  CellIndex CellOf(const Eigen::Vector2d& point) const;
  // Continuous cell coordinates of a point: integral at cell centres (what bicubic interpolation indexes).
  Eigen::Vector2d ToCellCoordinates(const Eigen::Vector2d& point) const {
    return (point - min_corner_) / options_.resolution_m - Eigen::Vector2d(0.5, 0.5);
  }
  // Cells above 0.65 occupied, observed cells below 0.196 free (map_server's thresholds), the rest unknown.
  OccupancyGrid ToOccupancyGrid() const;

 private:
  void GrowToInclude(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);
  void Update(CellIndex cell, float odds_factor, float first_value);
  void AddToField(const Eigen::Vector2d& hit);

  ProbabilityGridOptions options_;
  float hit_odds_;
  float miss_odds_;
  int width_ = 0;
  int height_ = 0;
  Eigen::Vector2d min_corner_ = Eigen::Vector2d::Zero();
  std::vector<float> probability_;
  std::vector<float> match_;
  std::vector<std::uint8_t> known_;
  std::vector<std::uint32_t> stamp_;  // the insertion that last touched each cell
  std::uint32_t insertion_ = 0;
};

}  // namespace corridor::nav
