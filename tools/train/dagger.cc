#include "tools/train/dagger.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "nav/learning/dpoom_demonstrations.h"
#include "nav/policy/morp_il.h"

namespace corridor::tools {
namespace {

scenario::ScenarioOptions Runs(const DaggerOptions& o, std::uint32_t seed, int worlds, int runs,
                               scenario::Policy policy) {
  scenario::ScenarioOptions run = o.protocol;
  run.seed = seed;
  run.worlds = worlds;
  run.runs = runs;
  run.only.reset();
  run.policies = {policy};
  run.trace = false;
  return run;
}

// Better on validation: more successes, then fewer collisions.
bool Better(const scenario::PolicySummary& a, const scenario::PolicySummary& b) {
  if (a.success != b.success) return a.success > b.success;
  return a.collision < b.collision;
}

}  // namespace

DaggerResult TrainMorpIl(const DaggerOptions& o, const std::function<void(const DaggerIteration&)>& progress) {
  if (o.iterations < 0 || o.train_worlds < 1 || o.train_runs < 1 || o.validate_worlds < 1 || o.validate_runs < 1 ||
      o.epochs < 1 || !(o.beta >= 0.0 && o.beta <= 1.0)) {
    throw std::invalid_argument("MORP-IL training: iterations >= 0, worlds, runs and epochs >= 1, beta in [0, 1]");
  }
  const nav::MorpIlOptions il;  // the history the graph's navigator is configured with
  const int inputs = il.history * nav::kMorpIlStepInputs;
  auto net = std::make_shared<nav::Mlp>(nav::DpoomNetwork(inputs, o.seed));
  nav::TrainingOptions training;
  training.adam.learning_rate = o.learning_rate;
  training.batch = o.batch;
  training.seed = o.seed;
  nav::MlpTrainer trainer(*net, training);
  nav::Examples data;
  DaggerResult result;
  for (int i = 0; i <= o.iterations; ++i) {
    DaggerIteration it;
    it.iteration = i;
    it.beta = i == 0 ? 1.0 : std::pow(o.beta, i);
    // Runs driven by the rules (the cloning) or by the mix, every step labelled with the rules' command.
    scenario::ScenarioOptions runs = Runs(o, o.train_seed + 1000U * static_cast<std::uint32_t>(i), o.train_worlds,
                                          o.train_runs, i == 0 ? scenario::Policy::kMorpRb : scenario::Policy::kMorpIl);
    runs.morp_il = std::make_shared<const nav::Mlp>(*net);
    runs.teach = std::make_shared<nav::Demonstrations>();
    runs.teach->beta = it.beta;
    runs.teach->random.seed(o.seed * 7919U + static_cast<std::uint64_t>(i));
    scenario::RunAll(runs);
    data.Append(runs.teach->Take(inputs));
    it.examples = data.size();
    double loss = 0.0;
    for (int epoch = 0; epoch < o.epochs; ++epoch) loss = trainer.Epoch(data.inputs, data.targets);
    it.train_rmse = std::sqrt(loss);
    // The network alone, on runs no training saw.
    scenario::ScenarioOptions validate =
        Runs(o, o.validate_seed, o.validate_worlds, o.validate_runs, scenario::Policy::kMorpIl);
    validate.morp_il = std::make_shared<const nav::Mlp>(*net);
    it.validation = scenario::Summarise(scenario::RunAll(validate)).at(0);
    if (result.iterations.empty() || Better(it.validation, result.iterations[result.best_iteration].validation)) {
      result.best = *net;
      result.best_iteration = i;
    }
    result.iterations.push_back(it);
    if (progress) progress(it);
  }
  return result;
}

}  // namespace corridor::tools
