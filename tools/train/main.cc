// corridor-train: trains the learned local policies' networks from seeded commands (docs/policies.md).
//   corridor-train morp-il  MORP-IL cloned from MORP-RB in the scenario runner (the daemon's graph in lockstep), then
//                           improved with DAgger (the paper's Algorithm 2); writes the shipped weights.
//   corridor-train takiguchi
//                           Takiguchi's direction network cloned from the safe-direction expert the same way.
//   corridor-train dpoom    behaviour cloning on DPoom's own demonstrations with the paper's split (d3_s3 held out),
//                           as DPoom's script does it: a check of the trainer against someone else's data and result.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "nav/learning/dpoom_demonstrations.h"
#include "nav/learning/mlp_training.h"
#include "tools/common/command_line.h"
#include "tools/train/dagger.h"

namespace {

using namespace corridor;
using tools::ParseNumber;

constexpr const char* kDaggerUsage = R"(usage: corridor-train morp-il|takiguchi [options]
morp-il: clones MORP-IL from MORP-RB; takiguchi: Takiguchi's direction network from the safe-direction expert
(nav/policy/takiguchi.h). Each from the expert driving scenario runs (the daemon's graph in lockstep), then DAgger:
runs driven by the expert at a share beta^i of the steps and by the network at the rest, labelled by the expert,
aggregated, trained on again. Keeps the network that succeeds most on validation runs (the network alone, seeds no
training used).
  --crowd KIND        paper or pacing (default), as corridor-scenario
  --pedestrians N     default 5
  --static N          static obstacles, default 0
  --laser             the robot carries the 2D laser (default: camera only)
  --train-seed N      iteration i's runs use N + 1000 i, default 1000
  --train-worlds N    per iteration, default 5
  --train-runs N      per world, default 2
  --validate-seed N   default 500000
  --validate-worlds N default 5
  --validate-runs N   default 2
  --iterations N      DAgger's after the cloning, default 3
  --beta B            default 0.5
  --epochs N          per iteration, default 30
  --learning-rate R   Adam's, default 1e-3
  --seed N            the network's initial weights, the order of the examples, the mixing; default 1
  --privileged        takiguchi: the expert labels from the simulator's people, not the tracker's
  --hidden N          takiguchi: hidden layers, default 3 (the paper's)
  --width N           takiguchi: units per hidden layer, default 256 (the paper's 2048 is over the step budget)
  --rays N            takiguchi: its rays, default 91 (the paper's)
  --field DEG         takiguchi: over how wide a field centred ahead, default 180 (the paper's); 360: all round
  --out FILE          the best network's weights (mlp.h's format)
  --json              the result as JSON on stdout
  --help
)";

constexpr const char* kUsage = R"(usage: corridor-train dpoom [options]
Clones a driver from DPoom's demonstrations (tests/data/dpoom_bc) with the paper's split: d3_s3.csv is the validation
recording; of the others' examples, a share drawn by the seed is the test set that picks the best epoch (as DPoom's
script does), the rest is trained on. Prints each epoch, then the validation RMSE of the best epoch's network against
the paper's 0.01477 and against repeating the last command.
  --data DIR          the recordings, default tests/data/dpoom_bc
  --history H         steps of history, default 4 (the paper's best): 12 H inputs
  --epochs N          default 200
  --patience N        stop after N epochs without a better test loss, default 50 (DPoom's script: 50)
  --learning-rate R   Adam's, default 1e-4 (DPoom's script: 1e-5 for about 1000 epochs)
  --batch N           default 32
  --test-share S      of the training recordings' examples, default 0.3
  --as-dpooms-script  also train on d3_s3, as DPoom's script does (it lists every recording for training, the
                      validation one among them): to compare with the paper's figure, not a held-out result
  --seed N            the initial weights, the test share and the order of the examples, default 1
  --out FILE          the best network's weights (mlp.h's format)
  --json              the result as JSON on stdout (no epochs)
  --help
)";

struct Options {
  std::filesystem::path data = "tests/data/dpoom_bc";
  int history = 4;
  int epochs = 200;
  int patience = 50;
  float learning_rate = 1e-4F;
  int batch = 32;
  double test_share = 0.3;
  std::uint64_t seed = 1;
  std::filesystem::path out;
  bool json = false;
  bool as_dpooms_script = false;
};

Options ParseOptions(int argc, char** argv) {
  Options o;
  for (tools::Arguments args(argc, argv, 2); args.Next();) {
    const std::string arg = args.current();
    const auto value = [&] { return args.Value(); };
    if (arg == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--data") {
      o.data = value();
    } else if (arg == "--history") {
      o.history = static_cast<int>(ParseNumber(arg, value(), 1, 20));
    } else if (arg == "--epochs") {
      o.epochs = static_cast<int>(ParseNumber(arg, value(), 1, 100000));
    } else if (arg == "--patience") {
      o.patience = static_cast<int>(ParseNumber(arg, value(), 1, 100000));
    } else if (arg == "--learning-rate") {
      o.learning_rate = static_cast<float>(ParseNumber(arg, value(), 1e-9, 1));
    } else if (arg == "--batch") {
      o.batch = static_cast<int>(ParseNumber(arg, value(), 1, 65536));
    } else if (arg == "--test-share") {
      o.test_share = ParseNumber(arg, value(), 0.01, 0.9);
    } else if (arg == "--seed") {
      o.seed = static_cast<std::uint64_t>(ParseNumber(arg, value(), 0, 1e15));
    } else if (arg == "--out") {
      o.out = value();
    } else if (arg == "--json") {
      o.json = true;
    } else if (arg == "--as-dpooms-script") {
      o.as_dpooms_script = true;
    } else {
      throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    }
  }
  return o;
}

int Run(const Options& o) {
  nav::Examples recorded;
  nav::Examples validation;
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(o.data)) {
    if (entry.path().extension() != ".csv") continue;
    const nav::Examples examples = nav::DpoomExamples(nav::ReadDpoomDemonstration(entry.path()), o.history);
    const bool held_out = entry.path().filename() == "d3_s3.csv";
    if (held_out) validation.Append(examples);
    if (!held_out || o.as_dpooms_script) recorded.Append(examples);
    ++files;
  }
  if (validation.size() == 0 || recorded.size() == 0) {
    throw std::runtime_error(o.data.string() + ": want DPoom's recordings, d3_s3.csv among them");
  }
  const auto [train, test] = nav::SplitExamples(recorded, o.test_share, o.seed);
  const int inputs = 12 * o.history;
  nav::Mlp net = nav::DpoomNetwork(inputs, o.seed);
  nav::TrainingOptions training;
  training.adam.learning_rate = o.learning_rate;
  training.batch = o.batch;
  training.seed = o.seed;
  nav::MlpTrainer trainer(net, training);
  nav::Mlp best = net;
  double best_test = INFINITY;
  int best_epoch = -1;
  for (int epoch = 0; epoch < o.epochs && epoch - best_epoch <= o.patience; ++epoch) {
    const double train_loss = trainer.Epoch(train.inputs, train.targets);
    const double test_loss = nav::Evaluate(net, nav::Loss::kMeanSquared, test.inputs, test.targets);
    if (test_loss < best_test) {
      best_test = test_loss;
      best_epoch = epoch;
      best = net;
    }
    if (!o.json) {
      std::printf("epoch %4d  train RMSE %.5f  test RMSE %.5f%s\n", epoch, std::sqrt(train_loss), std::sqrt(test_loss),
                  best_epoch == epoch ? "  (best)" : "");
      std::fflush(stdout);
    }
  }
  const double validation_rmse =
      std::sqrt(nav::Evaluate(best, nav::Loss::kMeanSquared, validation.inputs, validation.targets));
  const Eigen::MatrixXf predicted = best.ForwardBatch(validation.inputs);
  const auto output_rmse = [&](Eigen::Index row) {
    return std::sqrt((predicted.row(row) - validation.targets.row(row)).squaredNorm() /
                     static_cast<double>(validation.size()));
  };
  const double repeat = nav::RepeatLastCommandRmse(validation, o.history);
  const double test_repeat = nav::RepeatLastCommandRmse(test, o.history);
  if (!o.out.empty()) best.Save(o.out);
  if (o.json) {
    nlohmann::json result = {{"files", files},
                             {"train_examples", train.size()},
                             {"test_examples", test.size()},
                             {"validation_examples", validation.size()},
                             {"best_epoch", best_epoch},
                             {"test_rmse", std::sqrt(best_test)},
                             {"test_repeat_last_rmse", test_repeat},
                             {"validation_rmse", validation_rmse},
                             {"validation_rmse_linear", output_rmse(0)},
                             {"validation_rmse_angular", output_rmse(1)},
                             {"repeat_last_rmse", repeat},
                             {"paper_validation_error", 0.01477},
                             {"trained_on_validation", o.as_dpooms_script}};
    std::cout << result.dump(2) << '\n';
  } else {
    std::printf(
        "best epoch %d (test RMSE %.5f, repeating the last command %.5f); validation on d3_s3 (%lld examples): RMSE "
        "%.5f (linear %.5f, angular %.5f);"
        " repeating the last command %.5f; the paper 0.01477\n",
        best_epoch, std::sqrt(best_test), test_repeat, static_cast<long long>(validation.size()), validation_rmse,
        output_rmse(0), output_rmse(1), repeat);
  }
  return 0;
}

struct DaggerCommand {
  tools::DaggerOptions dagger;
  std::filesystem::path out;
  bool json = false;
};

DaggerCommand ParseDaggerCommand(int argc, char** argv, scenario::Policy learner) {
  DaggerCommand o;
  tools::DaggerOptions& d = o.dagger;
  d.learner = learner;
  d.protocol.crowd = scenario::CrowdKind::kPacing;
  d.protocol.pedestrians = 5;
  for (tools::Arguments args(argc, argv, 2); args.Next();) {
    const std::string arg = args.current();
    const auto value = [&] { return args.Value(); };
    const auto count = [&](double lo, double hi) { return static_cast<int>(ParseNumber(arg, value(), lo, hi)); };
    const auto seed = [&] { return static_cast<std::uint32_t>(ParseNumber(arg, value(), 0, 1 << 30)); };
    if (arg == "--help") {
      std::cout << kDaggerUsage;
      std::exit(0);
    } else if (arg == "--crowd") {
      const std::string name = value();
      const auto kind = scenario::ParseCrowdKind(name);
      if (!kind) throw std::invalid_argument("--crowd: paper or pacing, got '" + name + "'");
      d.protocol.crowd = *kind;
    } else if (arg == "--pedestrians") {
      d.protocol.pedestrians = count(0, 20);
    } else if (arg == "--static") {
      d.protocol.static_obstacles = count(0, 30);
    } else if (arg == "--laser") {
      d.protocol.laser = true;
    } else if (arg == "--train-seed") {
      d.train_seed = seed();
    } else if (arg == "--train-worlds") {
      d.train_worlds = count(1, 1000);
    } else if (arg == "--train-runs") {
      d.train_runs = count(1, 1000);
    } else if (arg == "--validate-seed") {
      d.validate_seed = seed();
    } else if (arg == "--validate-worlds") {
      d.validate_worlds = count(1, 1000);
    } else if (arg == "--validate-runs") {
      d.validate_runs = count(1, 1000);
    } else if (arg == "--iterations") {
      d.iterations = count(0, 100);
    } else if (arg == "--beta") {
      d.beta = ParseNumber(arg, value(), 0, 1);
    } else if (arg == "--epochs") {
      d.epochs = count(1, 100000);
    } else if (arg == "--learning-rate") {
      d.learning_rate = static_cast<float>(ParseNumber(arg, value(), 1e-9, 1));
    } else if (arg == "--seed") {
      d.seed = static_cast<std::uint64_t>(ParseNumber(arg, value(), 0, 1e15));
    } else if (arg == "--privileged") {
      d.privileged = true;
    } else if (arg == "--hidden") {
      d.hidden = count(1, 10);
    } else if (arg == "--width") {
      d.width = count(1, 4096);
    } else if (arg == "--rays") {
      d.protocol.takiguchi_rays = count(3, 10000);
    } else if (arg == "--field") {
      d.protocol.takiguchi_field_deg = count(1, 360);
    } else if (arg == "--out") {
      o.out = value();
    } else if (arg == "--json") {
      o.json = true;
    } else {
      throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    }
  }
  return o;
}

nlohmann::json ToJson(const tools::DaggerIteration& it) {
  return {
      {"iteration", it.iteration},
      {"beta", it.beta},
      {"examples", it.examples},
      {"train_loss", it.train_loss},
      {"train_accuracy", it.train_accuracy},
      {"validation_loss", it.validation_loss},
      {"validation_accuracy", it.validation_accuracy},
      {"training_runs", {{"runs", it.driven.runs}, {"success", it.driven.success}, {"collision", it.driven.collision}}},
      {"validation",
       {{"runs", it.validation.runs},
        {"success", it.validation.success},
        {"collision", it.validation.collision},
        {"timeout", it.validation.timeout},
        {"mean_time_to_goal_s", it.validation.mean_time_to_goal_s}}}};
}

int RunDagger(const DaggerCommand& o) {
  const bool classes = o.dagger.learner == scenario::Policy::kTakiguchi;
  const tools::DaggerResult result = tools::TrainPolicy(o.dagger, [&](const tools::DaggerIteration& it) {
    if (o.json) return;
    std::printf("iteration %d (beta %.3f): %lld examples, train %s %.4f", it.iteration, it.beta,
                static_cast<long long>(it.examples), classes ? "cross-entropy" : "RMSE", it.train_loss);
    if (classes) std::printf(", accuracy %.3f", it.train_accuracy);
    std::printf("; training runs success %.2f, collisions %.2f", it.driven.success, it.driven.collision);
    std::printf("; validation (%d runs) success %.2f, collisions %.2f, timeouts %.2f, %s %.4f", it.validation.runs,
                it.validation.success, it.validation.collision, it.validation.timeout,
                classes ? "cross-entropy" : "RMSE", it.validation_loss);
    if (classes) std::printf(", accuracy %.3f", it.validation_accuracy);
    std::printf("\n");
    std::fflush(stdout);
  });
  if (!o.out.empty()) result.best.Save(o.out);
  if (o.json) {
    nlohmann::json doc = {{"best_iteration", result.best_iteration}, {"iterations", nlohmann::json::array()}};
    for (const tools::DaggerIteration& it : result.iterations) doc["iterations"].push_back(ToJson(it));
    std::cout << doc.dump(2) << '\n';
  } else {
    std::printf("best: iteration %d\n", result.best_iteration);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode.empty() || mode == "--help") {
    std::cout << "usage: corridor-train morp-il|takiguchi|dpoom [options]   (corridor-train MODE --help)\n";
    return mode.empty() ? 2 : 0;
  }
  spdlog::set_level(spdlog::level::warn);  // the graph's own logs: only what goes wrong
  try {
    if (mode == "morp-il") return RunDagger(ParseDaggerCommand(argc, argv, scenario::Policy::kMorpIl));
    if (mode == "takiguchi") return RunDagger(ParseDaggerCommand(argc, argv, scenario::Policy::kTakiguchi));
    if (mode != "dpoom") throw std::invalid_argument("unknown mode '" + mode + "' (morp-il, takiguchi, dpoom)");
    return Run(ParseOptions(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corridor-train: %s\n", e.what());
    return 2;
  }
}
