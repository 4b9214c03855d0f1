#include "tools/train/dagger.h"

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "nav/learning/dpoom_demonstrations.h"
#include "nav/policy/demonstrations.h"
#include "nav/policy/morp_il.h"
#include "nav/policy/takiguchi.h"

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

// What differs between the policies trained: who teaches first, the network, the loss.
struct Learner {
  scenario::Policy expert;  // the policy driving the cloning runs
  int inputs = 0;
  nav::Mlp net;
  nav::Loss loss = nav::Loss::kMeanSquared;
};

Learner MakeLearner(const DaggerOptions& o) {
  if (o.learner == scenario::Policy::kMorpIl) {
    const nav::MorpIlOptions il;  // the history the graph's navigator is configured with
    const int inputs = il.history * nav::kMorpIlStepInputs;
    return {scenario::Policy::kMorpRb, inputs, nav::DpoomNetwork(inputs, o.seed), nav::Loss::kMeanSquared};
  }
  if (o.learner == scenario::Policy::kTakiguchi) {
    if (o.hidden < 1 || o.width < 1) throw std::invalid_argument("Takiguchi's network: hidden and width >= 1");
    const nav::TakiguchiOptions t = scenario::DirectionOptions(o.protocol);
    nav::CheckTakiguchiOptions(t);
    std::vector<int> sizes{nav::TakiguchiInputs(t)};
    for (int i = 0; i < o.hidden; ++i) sizes.push_back(o.width);
    sizes.push_back(nav::TakiguchiClasses(t));
    // Without a network, the navigator's expert drives the cloning runs.
    std::vector<nav::Activation> activations(static_cast<std::size_t>(o.hidden), nav::Activation::kRelu);
    activations.push_back(nav::Activation::kSoftmax);
    return {scenario::Policy::kTakiguchi, sizes.front(), nav::Mlp::Random(sizes, activations, o.seed),
            nav::Loss::kCrossEntropy};
  }
  throw std::invalid_argument(std::string("no training for policy ") + scenario::ToString(o.learner));
}

void SetNetwork(scenario::ScenarioOptions& runs, scenario::Policy policy, std::shared_ptr<const nav::Mlp> net) {
  (policy == scenario::Policy::kMorpIl ? runs.morp_il : runs.takiguchi) = std::move(net);
}

// A mean loss as reported: RMSE for the squared error, the cross-entropy itself.
double Reported(nav::Loss loss, double mean) { return loss == nav::Loss::kMeanSquared ? std::sqrt(mean) : mean; }

// The network's reported loss on examples and, for classes, the share it labels as the targets do.
std::pair<double, double> Score(const nav::Mlp& net, nav::Loss loss, const nav::Examples& examples) {
  const double mean = Reported(loss, nav::Evaluate(net, loss, examples.inputs, examples.targets));
  if (loss == nav::Loss::kMeanSquared) return {mean, 0.0};
  return {mean, nav::Accuracy(net, examples.inputs, examples.targets)};
}

}  // namespace

DaggerResult TrainPolicy(const DaggerOptions& o, const std::function<void(const DaggerIteration&)>& progress) {
  if (o.iterations < 0 || o.train_worlds < 1 || o.train_runs < 1 || o.validate_worlds < 1 || o.validate_runs < 1 ||
      o.epochs < 1 || !(o.beta >= 0.0 && o.beta <= 1.0)) {
    throw std::invalid_argument("training: iterations >= 0, worlds, runs and epochs >= 1, beta in [0, 1]");
  }
  Learner learner = MakeLearner(o);
  auto net = std::make_shared<nav::Mlp>(std::move(learner.net));
  nav::TrainingOptions training;
  training.loss = learner.loss;
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
    // Runs driven by the expert (the cloning) or by the mix, every step labelled by the expert.
    scenario::ScenarioOptions runs = Runs(o, o.train_seed + 1000U * static_cast<std::uint32_t>(i), o.train_worlds,
                                          o.train_runs, i == 0 ? learner.expert : o.learner);
    if (i > 0) SetNetwork(runs, o.learner, std::make_shared<const nav::Mlp>(*net));
    runs.teach = std::make_shared<nav::Demonstrations>();
    runs.privileged = o.privileged;
    runs.teach->beta = it.beta;
    runs.teach->random.seed(o.seed * 7919U + static_cast<std::uint64_t>(i));
    it.driven = scenario::Summarise(scenario::RunAll(runs)).at(0);
    data.Append(runs.teach->Take(learner.inputs));
    it.examples = data.size();
    double loss = 0.0;
    for (int epoch = 0; epoch < o.epochs; ++epoch) loss = trainer.Epoch(data.inputs, data.targets);
    it.train_loss = Reported(learner.loss, loss);  // the last epoch's, as it trained
    if (learner.loss == nav::Loss::kCrossEntropy) it.train_accuracy = nav::Accuracy(*net, data.inputs, data.targets);
    // The network alone, on runs no training saw; the expert labels its steps without driving any (beta 0).
    scenario::ScenarioOptions validate = Runs(o, o.validate_seed, o.validate_worlds, o.validate_runs, o.learner);
    SetNetwork(validate, o.learner, std::make_shared<const nav::Mlp>(*net));
    validate.teach = std::make_shared<nav::Demonstrations>();
    validate.teach->beta = 0.0;
    validate.privileged = o.privileged;
    it.validation = scenario::Summarise(scenario::RunAll(validate)).at(0);
    const nav::Examples held_out = validate.teach->Take(learner.inputs);
    if (held_out.size() > 0) std::tie(it.validation_loss, it.validation_accuracy) = Score(*net, learner.loss, held_out);
    if (result.iterations.empty() || BetterOnValidation(it, result.iterations[result.best_iteration])) {
      result.best = *net;
      result.best_iteration = i;
    }
    result.iterations.push_back(it);
    if (progress) progress(it);
  }
  return result;
}

bool BetterOnValidation(const DaggerIteration& a, const DaggerIteration& b) {
  if (a.validation.success != b.validation.success) return a.validation.success > b.validation.success;
  if (a.validation.collision != b.validation.collision) return a.validation.collision < b.validation.collision;
  return a.validation_loss < b.validation_loss;
}

}  // namespace corridor::tools
