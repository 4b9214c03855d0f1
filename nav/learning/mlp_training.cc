#include "nav/learning/mlp_training.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace corridor::nav {
namespace {

constexpr float kTinyProbability = 1e-12F;  // log(0) is not a loss

void CheckExamples(const Mlp& net, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                   const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  if (net.empty()) throw std::invalid_argument("an empty network");
  if (inputs.rows() != net.inputs() || targets.rows() != net.outputs() || inputs.cols() != targets.cols()) {
    throw std::invalid_argument("examples of " + std::to_string(inputs.rows()) + " inputs and " +
                                std::to_string(targets.rows()) + " targets (" + std::to_string(inputs.cols()) +
                                " and " + std::to_string(targets.cols()) + " of them) for a network of " +
                                std::to_string(net.inputs()) + " -> " + std::to_string(net.outputs()));
  }
}

// The loss of outputs against targets, a column each.
double LossOf(Loss loss, const Eigen::MatrixXf& outputs, const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  const auto n = static_cast<double>(outputs.cols());
  if (loss == Loss::kMeanSquared) return (outputs - targets).squaredNorm() / (n * static_cast<double>(outputs.rows()));
  return -(targets.array() * outputs.array().max(kTinyProbability).log()).sum() / n;
}

// The derivative of an activation by its input, from its output `a`, times `upstream`, in place.
void BackThrough(Activation activation, const Eigen::MatrixXf& a, Eigen::MatrixXf& upstream) {
  switch (activation) {
    case Activation::kIdentity:
    case Activation::kSoftmax:  // only last, under the cross-entropy: the loss's derivative already includes it
      return;
    case Activation::kRelu: upstream = (a.array() > 0.0F).select(upstream, 0.0F); return;
    case Activation::kTanh: upstream.array() *= 1.0F - a.array().square(); return;
    case Activation::kSigmoid: upstream.array() *= a.array() * (1.0F - a.array()); return;
  }
}

std::vector<DenseLayer> ZerosLike(const Mlp& net) {
  std::vector<DenseLayer> zeros;
  for (const DenseLayer& layer : net.layers()) {
    zeros.push_back({Eigen::MatrixXf::Zero(layer.weights.rows(), layer.weights.cols()),
                     Eigen::VectorXf::Zero(layer.bias.size()), layer.activation});
  }
  return zeros;
}

}  // namespace

void Examples::Append(const Examples& more) {
  if (more.size() == 0) return;
  if (size() > 0 && (more.inputs.rows() != inputs.rows() || more.targets.rows() != targets.rows())) {
    throw std::invalid_argument("examples of different sizes");
  }
  Eigen::MatrixXf all_inputs(more.inputs.rows(), size() + more.size());
  Eigen::MatrixXf all_targets(more.targets.rows(), size() + more.size());
  all_inputs << inputs, more.inputs;
  all_targets << targets, more.targets;
  inputs = std::move(all_inputs);
  targets = std::move(all_targets);
}

std::pair<Examples, Examples> SplitExamples(const Examples& all, double share, std::uint64_t seed) {
  if (!(share >= 0.0 && share <= 1.0)) throw std::invalid_argument("a share of " + std::to_string(share));
  std::vector<Eigen::Index> order(static_cast<std::size_t>(all.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::mt19937_64 random(seed);
  for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[random() % i]);
  const auto second = static_cast<Eigen::Index>(std::round(share * static_cast<double>(all.size())));
  const auto take = [&](Eigen::Index from, Eigen::Index count) {
    Examples part;
    part.inputs.resize(all.inputs.rows(), count);
    part.targets.resize(all.targets.rows(), count);
    for (Eigen::Index i = 0; i < count; ++i) {
      part.inputs.col(i) = all.inputs.col(order[static_cast<std::size_t>(from + i)]);
      part.targets.col(i) = all.targets.col(order[static_cast<std::size_t>(from + i)]);
    }
    return part;
  };
  return {take(second, all.size() - second), take(0, second)};
}

double Evaluate(const Mlp& net, Loss loss, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  CheckExamples(net, inputs, targets);
  if (inputs.cols() == 0) return 0.0;
  return LossOf(loss, net.ForwardBatch(inputs), targets);
}

double Accuracy(const Mlp& net, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  CheckExamples(net, inputs, targets);
  if (inputs.cols() == 0) return 0.0;
  const Eigen::MatrixXf outputs = net.ForwardBatch(inputs);
  int right = 0;
  for (Eigen::Index c = 0; c < outputs.cols(); ++c) {
    Eigen::Index got = 0;
    Eigen::Index want = 0;
    outputs.col(c).maxCoeff(&got);
    targets.col(c).maxCoeff(&want);
    right += got == want ? 1 : 0;
  }
  return static_cast<double>(right) / static_cast<double>(outputs.cols());
}

MlpTrainer::MlpTrainer(Mlp& net, const TrainingOptions& options) : net_(net), options_(options), random_(options.seed) {
  if (net_.empty()) throw std::invalid_argument("MlpTrainer: an empty network");
  if (options_.batch < 1) throw std::invalid_argument("MlpTrainer: batch must be 1 or more");
  if (!(options_.adam.learning_rate > 0.0F)) throw std::invalid_argument("MlpTrainer: learning_rate must be positive");
  const bool softmax_last = net_.layers().back().activation == Activation::kSoftmax;
  if (options_.loss == Loss::kCrossEntropy && !softmax_last) {
    throw std::invalid_argument("MlpTrainer: the cross-entropy needs a softmax last layer");
  }
  if (options_.loss == Loss::kMeanSquared && softmax_last) {
    throw std::invalid_argument("MlpTrainer: a softmax last layer trains on the cross-entropy");
  }
  gradient_ = ZerosLike(net_);
  first_moment_ = ZerosLike(net_);
  second_moment_ = ZerosLike(net_);
}

double MlpTrainer::Gradient(const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                            const Eigen::Ref<const Eigen::MatrixXf>& targets, std::vector<DenseLayer>& gradient) {
  CheckExamples(net_, inputs, targets);
  if (inputs.cols() == 0) throw std::invalid_argument("MlpTrainer: a batch of no examples");
  const std::vector<DenseLayer>& layers = net_.layers();
  activations_.resize(layers.size() + 1);
  activations_[0] = inputs;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    Eigen::MatrixXf& z = activations_[l + 1];
    z = layers[l].bias.replicate(1, inputs.cols());
    z.noalias() += layers[l].weights * activations_[l];
    Activate(layers[l].activation, z);
  }
  const Eigen::MatrixXf& outputs = activations_.back();
  const double loss = LossOf(options_.loss, outputs, targets);
  const auto n = static_cast<float>(inputs.cols());
  // The loss by the last layer's input (before its activation).
  Eigen::MatrixXf delta;
  if (options_.loss == Loss::kMeanSquared) {
    delta = (2.0F / (n * static_cast<float>(outputs.rows()))) * (outputs - targets);
    BackThrough(layers.back().activation, outputs, delta);
  } else {
    delta = (outputs - targets) / n;  // softmax and cross-entropy together
  }
  if (gradient.size() != layers.size()) gradient = ZerosLike(net_);
  for (std::size_t l = layers.size(); l-- > 0;) {
    gradient[l].weights.noalias() = delta * activations_[l].transpose();
    gradient[l].bias = delta.rowwise().sum();
    if (l == 0) break;
    Eigen::MatrixXf below = layers[l].weights.transpose() * delta;
    BackThrough(layers[l - 1].activation, activations_[l], below);
    delta = std::move(below);
  }
  return loss;
}

double MlpTrainer::Step(const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                        const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  const double loss = Gradient(inputs, targets, gradient_);
  ++steps_;
  const AdamOptions& adam = options_.adam;
  const float correction1 = 1.0F - std::pow(adam.beta1, static_cast<float>(steps_));
  const float root_correction2 = std::sqrt(1.0F - std::pow(adam.beta2, static_cast<float>(steps_)));
  const float step = adam.learning_rate / correction1;
  const auto update = [&](auto& value, const auto& g, auto& m, auto& v) {
    m = adam.beta1 * m + (1.0F - adam.beta1) * g;
    v = adam.beta2 * v + (1.0F - adam.beta2) * g.cwiseProduct(g);
    value.array() -= step * m.array() / (v.array().sqrt() / root_correction2 + adam.epsilon);
  };
  std::vector<DenseLayer>& layers = net_.layers();
  for (std::size_t l = 0; l < layers.size(); ++l) {
    update(layers[l].weights, gradient_[l].weights, first_moment_[l].weights, second_moment_[l].weights);
    update(layers[l].bias, gradient_[l].bias, first_moment_[l].bias, second_moment_[l].bias);
  }
  return loss;
}

double MlpTrainer::Epoch(const Eigen::Ref<const Eigen::MatrixXf>& inputs,
                         const Eigen::Ref<const Eigen::MatrixXf>& targets) {
  CheckExamples(net_, inputs, targets);
  const Eigen::Index count = inputs.cols();
  if (count == 0) return 0.0;
  order_.resize(static_cast<std::size_t>(count));
  std::iota(order_.begin(), order_.end(), Eigen::Index{0});
  // Fisher-Yates from the generator's own numbers: the same order whatever the standard library.
  for (std::size_t i = order_.size(); i > 1; --i) std::swap(order_[i - 1], order_[random_() % i]);
  Eigen::MatrixXf batch_inputs;
  Eigen::MatrixXf batch_targets;
  double sum = 0.0;
  int batches = 0;
  for (Eigen::Index start = 0; start < count; start += options_.batch) {
    const Eigen::Index size = std::min<Eigen::Index>(options_.batch, count - start);
    batch_inputs.resize(inputs.rows(), size);
    batch_targets.resize(targets.rows(), size);
    for (Eigen::Index i = 0; i < size; ++i) {
      const Eigen::Index column = order_[static_cast<std::size_t>(start + i)];
      batch_inputs.col(i) = inputs.col(column);
      batch_targets.col(i) = targets.col(column);
    }
    sum += Step(batch_inputs, batch_targets);
    ++batches;
  }
  return sum / batches;
}

}  // namespace corridor::nav
