// Scan matching over a large window, exactly, by branch and bound (Hess et al., ICRA 2016, section V-C; Olson, ICRA
// 2009, multi-resolution search): the grid is max-pooled into 2^h x 2^h blocks for h = 0..depth-1, a block's pooled
// score bounds every candidate inside it, and the search descends only into blocks whose bound beats the best
// candidate found so far. What loop closure and global relocalization search with.
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "nav/localization/hit_field.h"
#include "nav/localization/scan_matcher.h"

namespace corridor::nav {

class BranchAndBoundMatcher {
 public:
  // Precomputes the pooled grids of `grid`'s match values (a snapshot: later inserts into `grid` are not seen).
  // depth >= 1.
  BranchAndBoundMatcher(const HitField& grid, int depth = 7);

  // The best pose in the window around `guess` (linear_m, angular_rad; steps 0 = the grid's resolution and the
  // scan's angular step) whose score (mean match value, as ScanMatch) reaches min_score, or nullopt.
  std::optional<ScanMatch> Match(std::span<const Eigen::Vector2f> points, const Pose2& guess,
                                 const SearchWindow& window, double min_score) const;

  // The same over the whole grid and every heading.
  std::optional<ScanMatch> MatchEverywhere(std::span<const Eigen::Vector2f> points, double min_score) const;

  double resolution_m() const { return resolution_m_; }

 private:
  struct Level {
    int offset = 0;  // cell (x, y) of the grid is (x + offset, y + offset) here; the pooled grid covers
    int width = 0;   // windows that overlap the grid by at least one cell
    int height = 0;
    std::vector<float> max;  // max of the 2^h x 2^h cells starting at (x, y)
    float at(int x, int y) const {
      x += offset;
      y += offset;
      if (x < 0 || y < 0 || x >= width || y >= height) return 0.0f;
      return max[static_cast<std::size_t>(y) * width + x];
    }
  };
  struct Candidate;

  std::optional<ScanMatch> Search(std::span<const Eigen::Vector2f> points, const Pose2& centre, int linear_cells_x,
                                  int linear_cells_y, double angular_rad, double min_score) const;

  CellIndex CellOf(const Eigen::Vector2d& point) const {
    const Eigen::Vector2d c = (point - min_corner_) / resolution_m_;
    return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
  }

  double resolution_m_;
  Eigen::Vector2d min_corner_;
  int width_;
  int height_;
  std::vector<Level> levels_;  // levels_[0]: the grid's match values
};

}  // namespace corridor::nav
