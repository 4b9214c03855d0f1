// What a learned local policy is trained on: the local navigator (local_navigator.h), asked to teach, records each
// step's input and the expert's answer, and mixes who drives. Shared by MORP-IL (morp_il.h) and Takiguchi's direction
// network (takiguchi.h); filled by the scenario runner's runs for corridor-train (tools/train/dagger.h).
#pragma once

#include <functional>
#include <random>
#include <vector>

#include "nav/learning/mlp_training.h"
#include "nav/tracking/moving_objects.h"

namespace corridor::nav {

// Training (DAgger, the paper's Algorithm 2): at every step the navigator records the input and the expert's command
// (MORP-RB's, before the memory and evasion check it; for Takiguchi's network, the safe-direction expert's class,
// one-hot), and the robot drives with the expert's command at a share `beta` of the steps, drawn from `seed`, and with
// the learner's at the rest (always the expert's without a learner).
struct Demonstrations {
  double beta = 1.0;
  std::mt19937_64 random{1};
  std::vector<float> inputs;   // each step's input, one after the other
  std::vector<float> targets;  // the expert's answers, as the network's outputs (the same number each step)
  // Takiguchi's expert only: where the people really are (world frame), when the trainer knows it (the simulator's
  // crowd). The expert then labels with what the robot cannot see as well, the tracker's people replaced by these
  // ("learning by cheating", Chen et al., CoRL 2019). Empty: the tracker's view.
  std::function<std::vector<TrackedObject>()> people;

  // What was recorded since the last Take, as examples (one per column).
  Examples Take(int input_size);
};

}  // namespace corridor::nav
