// A binary Bayes occupancy grid in log-odds form (Thrun, Burgard and Fox, "Probabilistic Robotics", section 9.2;
// the ASNS stereovision system's map): each cell keeps l = log(p / (1 - p)); an observation adds the sensor model's
// log-odds for a hit or a miss, and l is clamped so that a cell can still change its mind.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct LogOddsOptions {
  double p_hit = 0.7;       // P(occupied | the beam ended in the cell)
  double p_miss = 0.4;      // P(occupied | the beam passed through the cell)
  double clamp_min = -2.0;  // log-odds bounds (about 0.12 and 0.97)
  double clamp_max = 3.5;
  double occupied_above = 0.65;  // probability thresholds for ToOccupancyGrid
  double free_below = 0.196;
};

class LogOddsGrid {
 public:
  // Same geometry as OccupancyGrid; every cell starts unknown (p = 0.5).
  LogOddsGrid(int width, int height, double resolution_m, Pose2 origin, const LogOddsOptions& options = {});

  // One observation of one cell. Cells outside the grid are ignored.
  void Update(CellIndex cell, bool hit);
  // A beam from `from` to `to` (map frame, metres): cells it crosses are misses; the last cell is a hit when
  // `hit` (the beam ended on something) and a miss otherwise (max range, nothing there).
  void IntegrateRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool hit);

  double Probability(CellIndex cell) const;
  double log_odds(CellIndex cell) const { return log_odds_[Index(cell)]; }
  // Thresholded into nav_msgs conventions: 100 occupied, 0 free, -1 unknown (never observed or undecided).
  OccupancyGrid ToOccupancyGrid() const;

 private:
  std::size_t Index(CellIndex c) const { return static_cast<std::size_t>(c.y) * geometry_.width() + c.x; }

  OccupancyGrid geometry_;  // cells unused: geometry only
  LogOddsOptions options_;
  double l_hit_;
  double l_miss_;
  std::vector<float> log_odds_;
  std::vector<std::uint8_t> observed_;
};

}  // namespace corridor::nav
