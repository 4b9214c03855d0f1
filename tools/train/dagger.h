// MORP-IL's training (DPoom, Kim et al., IEEE Access 2022, Section III.E, Algorithm 2): behaviour cloning from the
// rules (MORP-RB in the local navigator) driving scenario runs, then DAgger: runs driven by a mix of the rules and the
// network (the rules at a share beta^i of the steps in iteration i), every step labelled with the rules' command,
// aggregated, trained on again; the network that succeeds most on validation runs (other seeds, the network alone)
// is kept. Every run goes through the daemon's own graph in lockstep (tools/scenario).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "nav/learning/mlp_training.h"
#include "tools/scenario/scenario.h"

namespace corridor::tools {

struct DaggerOptions {
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
  double train_rmse = 0.0;             // of the last epoch
  scenario::PolicySummary validation;  // the network alone on the validation runs
};

struct DaggerResult {
  nav::Mlp best;
  int best_iteration = 0;
  std::vector<DaggerIteration> iterations;
};

// Throws std::invalid_argument for options that cannot train. `progress` (optional) hears of each iteration.
DaggerResult TrainMorpIl(const DaggerOptions& options,
                         const std::function<void(const DaggerIteration&)>& progress = nullptr);

}  // namespace corridor::tools
