// DPoom's recorded demonstrations (tests/data/dpoom_bc: a person driving DPoom in Gazebo among moving people, the
// data MORP-IL was cloned from; Kim et al., IEEE Access 2022, Sections III.E and IV.C) and the examples DPoom's own
// training script makes of them, so that corridor's trainer can be checked against someone else's data and result.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "nav/learning/mlp_training.h"

namespace corridor::nav {

// One row of a recording (about 35 a second).
struct DpoomRow {
  double time_s = 0.0;
  double goal_x_m = 0.0;  // the goal from the robot, in the world's axes
  double goal_y_m = 0.0;
  double linear_mps = 0.0;  // the command given at this row
  double angular_rps = 0.0;
  double yaw_rad = 0.0;              // the robot's heading in the world
  std::array<double, 7> deadends{};  // MORP's dead-end value of each of the 7 lanes, 0..360 (360: free)
};

// A recording that cannot be read: names the file and the line.
class DemonstrationFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The rows of one recording (a header line, then 13 numbers a line). Throws DemonstrationFileError.
std::vector<DpoomRow> ReadDpoomDemonstration(const std::filesystem::path& path);

// The examples DPoom's script makes of a recording with `history` steps (12 inputs a step, 48 for the paper's H = 4):
// the dead-ends of each step over 360, then each step's command (linear, angular), then the goal's x of each step, its
// y, and the yaw; the target is the next row's command. As that script does, the first `skip` rows are left out (the
// robot standing still at the start), and so are the last `history` rows. Throws std::invalid_argument for a history
// below 1.
Examples DpoomExamples(std::span<const DpoomRow> rows, int history, int skip = 10);

// A new network of DPoom's code's layers for `inputs` (12 a step of history: 48-48-96-144-48-2 for the paper's H = 4):
// the inputs' width, then twice, three times and once it again, with ReLU, then the command (linear, angular).
// Initialised from `seed` (Mlp::Random). MORP-IL's network has the same shape.
Mlp DpoomNetwork(int inputs, std::uint64_t seed);

// The root mean squared error of predicting each example's target as its last command (the input's command of the
// newest step): the baseline a cloned policy must beat. Same layout as DpoomExamples'.
double RepeatLastCommandRmse(const Examples& examples, int history);

}  // namespace corridor::nav
