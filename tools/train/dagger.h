// The learned local policies' training (DPoom, Kim et al., IEEE Access 2022, Section III.E, Algorithm 2): behaviour
// cloning from an expert driving scenario runs, then DAgger: runs driven by a mix of the expert and the network (the
// expert at a share beta^i of the steps in iteration i), every step labelled by the expert, aggregated, trained on
// again; the network that succeeds most on validation runs (other seeds, the network alone) is kept. Every run goes
// through the daemon's own graph in lockstep (tools/scenario).
//   - MORP-IL: the expert is the rules (MORP-RB in the local navigator); DPoom's layers; squared error.
//   - Takiguchi's direction network: the expert is the safe-direction expert (nav/policy/takiguchi.h) on what the
//     tracker shows; `hidden` layers of `width` ReLU units and a softmax over the 20 classes; cross-entropy.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "nav/learning/mlp_training.h"
#include "tools/scenario/scenario.h"

namespace corridor::tools {

struct DaggerOptions {
  scenario::Policy learner = scenario::Policy::kMorpIl;  // or kTakiguchi
  int hidden = 3;                                        // Takiguchi's network: the paper's 3 layers...
  int width = 256;                                       // ...of 2048; 256 meets the step budget
  bool privileged = false;  // Takiguchi's expert sees the simulator's people (ScenarioOptions::privileged)
  // The protocol of every run (world, crowd, obstacles, speeds); the seeds, worlds and runs below replace its own.
  scenario::ScenarioOptions protocol;
  std::uint32_t train_seed = 1000;  // iteration i's runs use train_seed + 1000 i
  int train_worlds = 5;
  int train_runs = 2;
  std::uint32_t validate_seed = 500000;  // never a training seed
  int validate_worlds = 5;
  int validate_runs = 2;
  int iterations = 3;  // DAgger's, after the cloning
  double beta = 0.5;
  int epochs = 30;  // per iteration, continuing from the network before
  float learning_rate = 1e-3F;
  int batch = 32;
  std::uint64_t seed = 1;  // the network's initial weights, the order of the examples, who drives each step
};

struct DaggerIteration {
  int iteration = 0;                   // 0: the cloning
  double beta = 1.0;                   // the share of steps the rules drove
  Eigen::Index examples = 0;           // aggregated so far
  double train_loss = 0.0;             // of the last epoch: RMSE (MORP-IL) or cross-entropy (Takiguchi)
  double train_accuracy = 0.0;         // Takiguchi: the share of training steps labelled as the expert did
  scenario::PolicySummary driven;      // the training runs, the expert and the network mixed
  scenario::PolicySummary validation;  // the network alone on the validation runs
  // Its steps there against the expert's labels (held out: no training saw them), as train_loss and train_accuracy.
  double validation_loss = 0.0;
  double validation_accuracy = 0.0;
};

struct DaggerResult {
  nav::Mlp best;
  int best_iteration = 0;
  std::vector<DaggerIteration> iterations;
};

// Which of two iterations' networks is kept: more successes on the validation runs, then fewer collisions, then the
// lower loss on their steps against the expert's labels (ten runs tie often; the loss tells networks that drive alike
// apart by how near the expert they stay where they drive themselves).
bool BetterOnValidation(const DaggerIteration& a, const DaggerIteration& b);

// Throws std::invalid_argument for options that cannot train. `progress` (optional) hears of each iteration.
DaggerResult TrainPolicy(const DaggerOptions& options,
                         const std::function<void(const DaggerIteration&)>& progress = nullptr);

}  // namespace corridor::tools
