// MORP-IL, DPoom's learned local policy (Kim et al., IEEE Access 2022, Sections III.E and IV.C-D, Algorithm 2): a
// small network maps MORP's dead-ends, the goal and the last commands over a history of H steps to the next command,
// cloned from an expert and improved with DAgger. In corridor the expert is MORP-RB inside the local navigator
// (local_navigator.h), and MORP-IL takes MORP-RB's place there: the navigator still keeps the path (the look-ahead
// point is the network's goal, done and replanning are its own), and its obstacle memory, evasion, the command gate
// and the speed zones still check every command the network gives.
//
// Inputs, 12 a step (48 for H = 4, the paper's layer sizes 48-48-96-144-48-2), oldest step first:
//   - MORP's lanes in 7 bins from left to right (the paper's 7 lanes): each the nearest dead-end in the bin over
//     lane_range_m, capped at 1 (1: free that far; 0: blind, something too near to see);
//   - the command the robot was given after the step before (linear over max_linear_mps, angular over
//     max_angular_rps);
//   - the goal (the look-ahead point, or the goal itself on the final approach): its bearing over pi and its distance
//     over goal_range_m, capped at 1;
//   - 1 on the final approach, else 0.
// Outputs: the command, linear over max_linear_mps and angular over max_angular_rps.
#pragma once

#include <deque>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/ground/morp.h"
#include "nav/learning/mlp.h"

namespace corridor::nav {

struct MorpIlOptions {
  int history = 4;  // H: steps of inputs
  double lane_range_m = 3.0;
  double goal_range_m = 2.0;
  // The scale of the commands in and out, the network's own (what it was trained with: the shipped one at DPoom's
  // 0.26 m/s and the path follower's 1.5 rad/s), not the robot's limits, which cap its commands afterwards.
  double max_linear_mps = 0.26;
  double max_angular_rps = 1.5;
};

inline constexpr int kMorpIlStepInputs = 12;
inline constexpr int kMorpIlLaneBins = 7;

// The inputs over the last `history` steps. Before `history` steps have been pushed, the oldest is repeated.
class MorpIlFeatures {
 public:
  explicit MorpIlFeatures(const MorpIlOptions& options);  // throws std::invalid_argument for bad options

  // One step: this frame's lanes (left to right; empty: nothing seen, all blind), the bearing (radians, positive to
  // the left) and distance of the goal, whether it is the final approach, and the command given after the step
  // before.
  void Push(const std::vector<LaneResult>& lanes, double goal_bearing_rad, double goal_distance_m, bool final_approach,
            const Twist2& last_command);
  void Clear() { steps_.clear(); }
  int size() const { return options_.history * kMorpIlStepInputs; }
  // The network's input: `size()` values, oldest step first. Zeros before the first Push.
  Eigen::VectorXf Input() const;

 private:
  MorpIlOptions options_;
  std::deque<Eigen::Matrix<float, kMorpIlStepInputs, 1>> steps_;
};

// The network's command for an input, scaled back to m/s and rad/s and kept within the limits.
Twist2 MorpIlCommand(const Mlp& net, const Eigen::VectorXf& input, const MorpIlOptions& options);

// A network MORP-IL can drive with: `history` x 12 inputs, 2 outputs. Throws std::invalid_argument otherwise.
void CheckMorpIlNetwork(const Mlp& net, const MorpIlOptions& options);

}  // namespace corridor::nav
