// Takiguchi et al.'s safe-direction network: what is around the robot, seen along 91 rays over the front 180 degrees
// (how far, and how fast and which way what is there moves, from accumulated laser scans: corridor's tracker,
// nav/tracking/moving_objects.h) and the goal's direction go to a network that picks one of 19 headings, every 10
// degrees from the robot's right to its left, or stopping. A heading becomes a command through a heading
// controller (turn toward it in proportion to the error, drive on as the robot faces it).
//
// Inputs (274 for 91 rays), rays from the robot's right (-90 degrees) to its left (+90) every 2 degrees (the paper's;
// field_rad 2 pi spreads them evenly all round instead, from straight behind, so that what the tracker keeps of people
// who left a forward camera's view reaches the network too):
//   - distances: the nearest thing along each ray over range_m, capped at 1 (1: nothing that near);
//   - speeds: the speed of the moving object a ray meets over max_object_speed_mps, capped at 1 (0: a standing
//     thing, or nothing);
//   - directions: the way that object moves, against coming straight down the ray at the robot, over pi: 0 walking
//     straight at the robot, +-0.5 crossing the ray, +-1 walking straight away (0 without a moving object);
//   - the goal's bearing over pi (positive to the left).
// The direction is measured from "coming at the robot" so that the cut at +-pi falls on what matters least.
//
// The labels come from an expert written here after ORCA's velocity obstacles (van den Berg et al., 2011; RVO2 is
// not in Debian): of the 20 choices, those that meet nobody within the horizon are safe, and the safe one nearest the
// goal is the label; when none is safe, the one that meets someone latest. ORCA's choices are velocities a
// holonomic robot takes at once; a differential base turns first, so each choice here is driven as the heading
// controller drives it (the heading held in the world from the start), people predicted at their velocity, and meets
// someone when it comes within reach while closing in. People who do not see the robot do not take half the
// avoidance, so none is shared out as in ORCA's reciprocal half-planes. "Nearest the goal" is ORCA's nearest to the
// preferred velocity made to work for a robot that cannot go sideways or back: a heading costs its angle from the
// goal's bearing (a goal behind counts at the nearer side, so the robot turns toward it) and stopping costs as much as
// a detour of stop_cost_rad (for a goal ahead, 60 degrees is where a velocity at full speed is as far from the
// preferred one as standing still).
#pragma once

#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/learning/mlp.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

struct TakiguchiOptions {
  int rays = 91;                        // over the field (both edges included, but once all round)
  double field_rad = std::numbers::pi;  // centred ahead; (0, 2 pi]
  double range_m = 5.0;                 // farther than this along a ray is nothing
  double max_object_speed_mps = 1.5;    // speeds on this scale
  // A tracked object counts at least this large (a laser sees a person's near side only); a static point is a disc
  // of point_radius_m.
  double min_object_radius_m = 0.25;
  double point_radius_m = 0.05;
  int headings = 19;  // every 180 / (headings - 1) degrees from the right to the left; then stop
  // The heading controller: turn at k_heading times the heading error (at most max_angular_rps), drive at
  // max_linear_mps times the error's cosine, and turn on the spot beyond turn_in_place_rad.
  double max_linear_mps = 0.26;
  double max_angular_rps = 1.5;
  double k_heading = 2.0;
  double turn_in_place_rad = 1.0;
};

// 3 x rays + 1 inputs, headings + 1 classes (the last: stop).
int TakiguchiInputs(const TakiguchiOptions& options);
int TakiguchiClasses(const TakiguchiOptions& options);
// Throws std::invalid_argument naming the bad option.
void CheckTakiguchiOptions(const TakiguchiOptions& options);

// The network's input for the robot at `robot` (world frame) among `around` (world frame) with its goal at
// goal_bearing_rad (robot frame, positive to the left).
Eigen::VectorXf TakiguchiInput(const Pose2& robot, const Surroundings& around, double goal_bearing_rad,
                               const TakiguchiOptions& options);

// A class's heading in the robot frame (radians, positive to the left); none for stop. Throws std::out_of_range
// for a class that is not one.
std::optional<double> TakiguchiHeading(int klass, const TakiguchiOptions& options);
// The heading controller's command for a heading error (robot frame; positive: the heading is to the left).
Twist2 HeadingControl(double error_rad, const TakiguchiOptions& options);
// Its command for a class.
Twist2 TakiguchiCommand(int klass, const TakiguchiOptions& options);
// A network the policy can drive with: TakiguchiInputs inputs, TakiguchiClasses outputs. Throws
// std::invalid_argument otherwise.
void CheckTakiguchiNetwork(const Mlp& net, const TakiguchiOptions& options);

// The expert's view of one thing to keep clear of (world frame).
struct DiscMover {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  double radius_m = 0.25;
};

struct SafeDirectionOptions {
  double robot_radius_m = 0.2;
  double margin_m = 0.1;   // kept beyond both radii
  double horizon_s = 3.0;  // ORCA's tau: a choice meeting nobody within it is safe
  double step_s = 0.1;     // of the prediction
  double stop_cost_rad = std::numbers::pi / 3;
};

// Where the robot at `robot` (world frame) goes following class `klass` with the heading controller, the heading held
// in the world from the start: its positions every step_s to the horizon (step_s first).
std::vector<Eigen::Vector2d> DriveClass(const Pose2& robot, int klass, const TakiguchiOptions& options,
                                        const SafeDirectionOptions& safe);
// When the robot driving `drive` (positions every step_s, from `start`) first comes within reach of `mover` (their
// discs and the margin touch) while closing in; infinity when it does not.
double TimeToMeet(const Eigen::Vector2d& start, const std::vector<Eigen::Vector2d>& drive, const DiscMover& mover,
                  const SafeDirectionOptions& options);

// The expert's label for the robot at `robot` (world frame) among `movers` (people and static points alike) with
// its goal at goal_bearing_rad (robot frame).
int SafeDirectionLabel(const Pose2& robot, const std::vector<DiscMover>& movers, double goal_bearing_rad,
                       const TakiguchiOptions& options, const SafeDirectionOptions& safe);

// What the tracker shows, as the expert's movers: tracked objects at their size (at least min_object_radius_m) and
// static points as discs of point_radius_m, within reach_m of `robot` (world frame).
std::vector<DiscMover> MoversAround(const Eigen::Vector2d& robot, const Surroundings& around, double reach_m,
                                    const TakiguchiOptions& options);

}  // namespace corridor::nav
