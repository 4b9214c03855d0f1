// Simulated people and unmapped objects for the simulator: static obstacles (cylinders and boxes standing on the
// floor) and pedestrians walking between their own two points: back and forth for ever, or once and then standing
// at the end (the DPoom evaluation's agents).
//
// Pedestrians avoid each other and the static obstacles with ORCA, optimal reciprocal collision avoidance (van den
// Berg, Guy, Lin and Manocha, "Reciprocal n-body collision avoidance", ISRR 2011): each one's new velocity is the
// one nearest its preferred velocity inside the half-planes that keep it clear of every neighbour for a time
// horizon, each pair taking half of the avoidance. They do not see the robot, as in the DPoom evaluation: avoiding
// them is the robot's job alone. Walls and the static obstacles are kept by routes chosen along clear straight
// lines and by refusing moves into the world's collision grid; ORCA also avoids the static obstacles (as neighbours
// that do not move) when other people push someone toward them.
//
// Written here rather than taken from RVO2: Debian packages no ORCA library, and the algorithm (two small linear
// programs in the velocity plane) is about two hundred lines; see docs/design.md.
#pragma once

#include <functional>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "drivers/sim/world.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::drivers::sim {

struct PedestrianRoute {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
};

struct CrowdOptions {
  double radius_m = 0.25;  // a person's footprint
  double height_m = 1.7;
  double preferred_speed_mps = 0.8;
  double max_speed_mps = 1.2;
  double time_horizon_s = 2.0;  // ORCA: velocities are kept collision-free this far ahead
  double neighbour_distance_m = 5.0;
  double goal_tolerance_m = 0.3;  // this near a route's end a person has reached it
  // At a route's end a person turns back, walking it to and fro for ever; false: stands there for good, as the
  // agents of the DPoom evaluation stop at their targets.
  bool turn_back = true;
  // People aim this much to the right of their goal, as people keep right: it breaks the symmetric standoffs in
  // which ORCA agents walking straight at each other would slow to a stop face to face.
  double keep_right_rad = 0.1;
  // People see the robot and keep clear of it as of each other, but taking all of the avoidance (a robot is not
  // counted on to give way). False: they walk as if it were not there, as in the DPoom evaluation.
  bool see_robot = false;
};

struct Pedestrian {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  PedestrianRoute route;
  bool returning = false;  // walking from goal back to start
  bool arrived = false;    // standing at the goal for good (CrowdOptions::turn_back false)
};

// A disc a person keeps clear of: another person, an obstacle or the robot; `reciprocal` when it takes half of the
// avoidance (another person walking).
struct OrcaNeighbour {
  Eigen::Vector2d position;
  Eigen::Vector2d velocity;
  double radius_m;
  bool reciprocal;
};

class Crowd {
 public:
  // `world` must outlive the crowd; its obstacles are avoided, its collision grid's walls kept. Each pedestrian
  // starts at its route's start.
  Crowd(const World& world, std::vector<PedestrianRoute> routes, const CrowdOptions& options);

  // `robot`: the robot's disc and velocity (world frame), kept clear of when CrowdOptions::see_robot.
  void Step(double dt_s, const std::optional<OrcaNeighbour>& robot = std::nullopt);
  const std::vector<Pedestrian>& pedestrians() const { return pedestrians_; }
  const CrowdOptions& options() const { return options_; }
  bool empty() const { return pedestrians_.empty(); }

  // Every pedestrian as a closed prism of their footprint and height, coloured, for ray casting.
  TriangleMesh Mesh() const;

 private:
  bool Free(const Eigen::Vector2d& p) const;  // a person's footprint here is clear of the collision grid

  const nav::OccupancyGrid& collision_;
  const std::vector<StaticObstacle>& obstacles_;
  CrowdOptions options_;
  std::vector<Pedestrian> pedestrians_;
};

// The velocity nearest `preferred` within speed `max_speed` that keeps `self` (at `position`, moving at `velocity`)
// clear of every other disc for `time_horizon_s`. Others with `reciprocal` share the avoidance; static ones do not.
Eigen::Vector2d OrcaVelocity(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity, double radius_m,
                             const Eigen::Vector2d& preferred, double max_speed, double time_horizon_s, double dt_s,
                             const std::vector<OrcaNeighbour>& neighbours);

// Where RandomRoutes puts routes.
struct RouteArea {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double within_m = 1e3;     // starts within this distance of `center`
  double clearance_m = 0.0;  // ... but no nearer than this (people do not appear on the robot)
  double min_length_m = 4.0;
  double max_length_m = 10.0;
  // Where starts and goals may lie besides free space (a band across the robot's way, say); empty: anywhere.
  std::function<bool(const Eigen::Vector2d&)> contains;
  // Goals kept as far apart as starts are, for people who stand at their goals (CrowdOptions::turn_back false).
  bool goals_apart = false;
};

// Random routes for `count` people of `radius_m` in free space of `collision`, in `area`, each along a clear
// straight line (the person's radius plus a margin), their starts apart. Fewer when the area has no room.
std::vector<PedestrianRoute> RandomRoutes(const nav::OccupancyGrid& collision, int count, double radius_m,
                                          const RouteArea& area, std::mt19937& rng);

}  // namespace corridor::drivers::sim
