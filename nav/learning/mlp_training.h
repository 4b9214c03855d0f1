// Training an Mlp (mlp.h) on examples: minibatches, back-propagation and Adam (Kingma and Ba, ICLR 2015, Algorithm
// 1, with PyTorch's defaults), on the mean squared error (PyTorch's MSELoss: the mean over every output of every
// example) or the cross-entropy of a softmax output against one-hot targets. Deterministic for a seed: the same
// network, examples and seed give the same weights, bit for bit, on the same machine and build.
#pragma once

#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "nav/learning/mlp.h"

namespace corridor::nav {

enum class Loss {
  kMeanSquared,   // any last layer; targets are the wanted outputs
  kCrossEntropy,  // the last layer must be a softmax; targets are one-hot columns (or class probabilities)
};

struct AdamOptions {
  float learning_rate = 1e-3F;
  float beta1 = 0.9F;
  float beta2 = 0.999F;
  float epsilon = 1e-8F;
};

struct TrainingOptions {
  Loss loss = Loss::kMeanSquared;
  AdamOptions adam;
  int batch = 32;          // examples per step (the last of an epoch may be smaller)
  std::uint64_t seed = 1;  // the order of the examples in each epoch
};

// Examples to learn from, one per column: the inputs and the outputs wanted.
struct Examples {
  Eigen::MatrixXf inputs;
  Eigen::MatrixXf targets;

  Eigen::Index size() const { return inputs.cols(); }
  // Appends `more` (of the same sizes; std::invalid_argument otherwise).
  void Append(const Examples& more);
};

// `all` dealt in two at random (drawn by `seed`): the second part holds `share` of the examples, rounded. Throws
// std::invalid_argument for a share outside [0, 1].
std::pair<Examples, Examples> SplitExamples(const Examples& all, double share, std::uint64_t seed);
// The loss of `net` on examples (one per column of `inputs` and `targets`): the mean squared error, or the mean
// cross-entropy. Throws std::invalid_argument for mismatched sizes.
double Evaluate(const Mlp& net, Loss loss, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                const Eigen::Ref<const Eigen::MatrixXf>& targets);
// The share of examples whose largest output is where their target's largest value is.
double Accuracy(const Mlp& net, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                const Eigen::Ref<const Eigen::MatrixXf>& targets);

// Trains one network in place; the network must outlive the trainer and keep its shape. Not thread-safe.
class MlpTrainer {
 public:
  // Throws std::invalid_argument for a batch below 1, a learning rate that is not positive, a cross-entropy without
  // a softmax last layer, or a softmax last layer under the squared error.
  MlpTrainer(Mlp& net, const TrainingOptions& options);

  // One pass over the examples in an order drawn from the seed; returns the mean loss of its steps.
  double Epoch(const Eigen::Ref<const Eigen::MatrixXf>& inputs, const Eigen::Ref<const Eigen::MatrixXf>& targets);
  // One Adam step on one batch (a column each); returns the batch's loss before the step.
  double Step(const Eigen::Ref<const Eigen::MatrixXf>& inputs, const Eigen::Ref<const Eigen::MatrixXf>& targets);
  // The gradient of the batch's loss by every weight and bias, in the layers' shapes (for the tests' check against
  // finite differences); returns the loss.
  double Gradient(const Eigen::Ref<const Eigen::MatrixXf>& inputs, const Eigen::Ref<const Eigen::MatrixXf>& targets,
                  std::vector<DenseLayer>& gradient);

  int steps() const { return steps_; }

 private:
  Mlp& net_;
  TrainingOptions options_;
  std::mt19937_64 random_;
  int steps_ = 0;
  std::vector<DenseLayer> gradient_;
  std::vector<DenseLayer> first_moment_;
  std::vector<DenseLayer> second_moment_;
  std::vector<Eigen::MatrixXf> activations_;  // each layer's output in the last pass (the input first)
  std::vector<Eigen::Index> order_;
};

}  // namespace corridor::nav
