// Scan matching: the pose at which a scan's points fall on the walls a grid holds (its match values: the likelihood
// field of the hits, see hit_field.h).
//
// Two steps, as in Cartographer's local SLAM (Hess et al., ICRA 2016, section V): a correlative search over a small
// window around a guess (Olson, "Real-time correlative scan matching", ICRA 2009, section III: every candidate pose
// scored by the sum of the grid's match values at the points), then a least-squares refinement with Ceres over the
// grid's bicubic interpolation, pulled towards a prior pose so that a corridor's unconstrained direction stays where
// the odometry put it.
#pragma once

#include <span>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/localization/hit_field.h"

namespace corridor::nav {

struct SearchWindow {
  double linear_m = 0.15;         // +- in x and y around the guess
  double angular_rad = 0.14;      // +- around the guess's heading
  double linear_step_m = 0.0;     // rounded to whole cells of the grid, at least one (0: one cell)
  double angular_step_rad = 0.0;  // 0: the angle that moves the scan's farthest point by one cell
  // A candidate's score is multiplied by exp(-(translation_cost * d^2 + rotation_cost * a^2)) for its distance d (m)
  // and angle a (rad) from the guess, so that among equals the guess's neighbourhood wins (Cartographer's defaults).
  double translation_cost = 0.1;
  double rotation_cost = 0.1;
};

struct ScanMatch {
  Pose2 pose;          // the grid's frame
  double score = 0.0;  // mean match value at the scan's points at `pose`, in [0, 1]
};

// The best pose in the window around `guess` for `points` (base frame); the guess itself when nothing scores higher.
// Every pose is scored: use for small windows (BranchAndBoundMatcher for large ones).
ScanMatch CorrelativeMatch(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& guess,
                           const SearchWindow& window);

// The mean match value at the points with the robot at `pose`.
double ScoreAt(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& pose);

struct RefineOptions {
  // Residual weights (Cartographer's defaults): each point's (1 - match value), scaled by 1 / sqrt(points); the
  // distance to the prior's position; the angle to its heading.
  double occupied_weight = 1.0;
  double translation_weight = 10.0;
  double rotation_weight = 40.0;
  int max_iterations = 20;
};

// Refines `start` by least squares on the grid's bicubic interpolation, with the prior's position and heading as
// soft constraints. Returns `start` when the grid is empty or there are no points.
Pose2 RefineMatch(const HitField& grid, std::span<const Eigen::Vector2f> points, const Pose2& start, const Pose2& prior,
                  const RefineOptions& options = {});

}  // namespace corridor::nav
