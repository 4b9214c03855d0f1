// Frontier exploration (Yamauchi, "A frontier-based approach for autonomous exploration", CIRA 1997): where the map
// being built has free floor next to unknown space (and not next to a wall: the unknown gaps between a wall's hits are
// not rooms), driving there shows what lies beyond. Each frontier's goal is the place nearest its centroid that is
// safely inside known free space and reachable; the next goal is the nearest of those by driving distance.
// Exploration is over when no frontier is left that the robot can reach.
//
// Written here: Debian packages no explore_lite or m-explore outside ROS; the search is a Dijkstra pass and a look
// around each frontier's centroid.
#pragma once

#include <optional>
#include <span>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

struct FrontierOptions {
  double clearance_m = 0.35;       // a goal (and the way to it) is this far from anything not known to be free
  double min_frontier_m = 0.3;     // smaller frontiers (gaps between a wall's hits) are not worth a drive
  double view_distance_m = 1.5;    // the goal is at most this far from its frontier's centroid
  double given_up_radius_m = 0.5;  // goals this near one given up (unreachable, or reached without seeing more) are not
                                   // offered again
};

struct FrontierGoal {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // map frame
  double path_m = 0.0;                                 // driving distance from the robot, along free cells
  int frontiers = 0;                                   // reachable frontiers in the map, this one included
};

// The next place to drive to in `map` (being built, -1 unknown, 0 free, 100 occupied) for the robot at `robot`, or
// nullopt when no reachable frontier is left (exploration is over). `given_up`: goals not to offer again.
std::optional<FrontierGoal> NextFrontierGoal(const OccupancyGrid& map, const Eigen::Vector2d& robot,
                                             std::span<const Eigen::Vector2d> given_up,
                                             const FrontierOptions& options = {});

}  // namespace corridor::nav
