#include "nav/learning/mlp_training.h"

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

// Checks the back-propagated gradient of every weight and bias against central differences of the loss.
void ExpectGradientMatchesDifferences(Mlp net, Loss loss, const Eigen::MatrixXf& inputs,
                                      const Eigen::MatrixXf& targets) {
  TrainingOptions options;
  options.loss = loss;
  MlpTrainer trainer(net, options);
  std::vector<DenseLayer> gradient;
  trainer.Gradient(inputs, targets, gradient);
  constexpr float kStep = 1e-2F;
  int checked = 0;
  for (std::size_t l = 0; l < net.layers().size(); ++l) {
    const auto check = [&](float& value, float analytic, const char* what, Eigen::Index i) {
      const float kept = value;
      value = kept + kStep;
      const double up = Evaluate(net, loss, inputs, targets);
      value = kept - kStep;
      const double down = Evaluate(net, loss, inputs, targets);
      value = kept;
      const double numeric = (up - down) / (2.0 * kStep);
      EXPECT_NEAR(analytic, numeric, 2e-3 + 0.03 * std::abs(numeric)) << "layer " << l << " " << what << " " << i;
      ++checked;
    };
    DenseLayer& layer = net.layers()[l];
    for (Eigen::Index i = 0; i < layer.weights.size(); ++i) {
      check(layer.weights.data()[i], gradient[l].weights.data()[i], "weight", i);
    }
    for (Eigen::Index i = 0; i < layer.bias.size(); ++i) check(layer.bias(i), gradient[l].bias(i), "bias", i);
  }
  EXPECT_EQ(static_cast<std::size_t>(checked), net.parameter_count());
}

Eigen::MatrixXf Normal(Eigen::Index rows, Eigen::Index cols, std::uint32_t seed, float sigma = 1.0F) {
  std::mt19937 random(seed);
  std::normal_distribution<float> normal(0.0F, sigma);
  Eigen::MatrixXf m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) = normal(random);
  return m;
}

Eigen::MatrixXf OneHot(const std::vector<int>& classes, int count) {
  Eigen::MatrixXf m = Eigen::MatrixXf::Zero(count, static_cast<Eigen::Index>(classes.size()));
  for (std::size_t i = 0; i < classes.size(); ++i) m(classes[i], static_cast<Eigen::Index>(i)) = 1.0F;
  return m;
}

TEST(MlpTrainingTest, GradientIsTheLossesSlopeForEveryLossAndActivation) {
  const Eigen::MatrixXf inputs = Normal(5, 7, 1);
  ExpectGradientMatchesDifferences(
      Mlp::Random(std::array{5, 6, 4, 3}, std::array{Activation::kTanh, Activation::kSigmoid, Activation::kIdentity},
                  2),
      Loss::kMeanSquared, inputs, Normal(3, 7, 3));
  ExpectGradientMatchesDifferences(
      Mlp::Random(std::array{5, 6, 3}, std::array{Activation::kSigmoid, Activation::kTanh}, 4), Loss::kMeanSquared,
      inputs, Normal(3, 7, 5, 0.5F));
  ExpectGradientMatchesDifferences(
      Mlp::Random(std::array{5, 8, 4}, std::array{Activation::kTanh, Activation::kSoftmax}, 6), Loss::kCrossEntropy,
      inputs, OneHot({0, 1, 2, 3, 3, 2, 1}, 4));
  // ReLU's kink: inputs kept away from it by a large bias, so that a step of the difference does not cross it.
  Mlp relu = Mlp::Random(std::array{5, 6, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 7);
  relu.layers()[0].bias.head(3).setConstant(3.0F);
  relu.layers()[0].bias.tail(3).setConstant(-3.0F);
  relu.layers()[0].weights *= 0.3F;
  ExpectGradientMatchesDifferences(relu, Loss::kMeanSquared, inputs, Normal(2, 7, 8));
}

TEST(MlpTrainingTest, LearnsASmoothFunctionItWasNotShownAllOf) {
  // y = (sin(2 x0) cos(x1), x0 x1 / 2) over [-1.5, 1.5]^2: fitted on 2000 points, judged on 500 others.
  const auto make = [](int count, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> u(-1.5F, 1.5F);
    Eigen::MatrixXf x(2, count);
    Eigen::MatrixXf y(2, count);
    for (int i = 0; i < count; ++i) {
      x(0, i) = u(random);
      x(1, i) = u(random);
      y(0, i) = std::sin(2.0F * x(0, i)) * std::cos(x(1, i));
      y(1, i) = 0.5F * x(0, i) * x(1, i);
    }
    return std::pair{x, y};
  };
  const auto [train_x, train_y] = make(2000, 1);
  const auto [test_x, test_y] = make(500, 2);
  Mlp net =
      Mlp::Random(std::array{2, 32, 32, 2}, std::array{Activation::kTanh, Activation::kTanh, Activation::kIdentity}, 3);
  const double before = Evaluate(net, Loss::kMeanSquared, test_x, test_y);
  TrainingOptions options;
  options.adam.learning_rate = 3e-3F;
  MlpTrainer trainer(net, options);
  for (int epoch = 0; epoch < 150; ++epoch) trainer.Epoch(train_x, train_y);
  const double after = Evaluate(net, Loss::kMeanSquared, test_x, test_y);
  EXPECT_GT(before, 0.1);
  EXPECT_LT(after, 0.003) << "from " << before;
  EXPECT_EQ(trainer.steps(), 150 * 63);  // 2000 examples in batches of 32
}

TEST(MlpTrainingTest, ClassifiesThreeSpiralsItWasNotShownAllOf) {
  // Three interleaved spiral arms, one class each: no straight line separates them.
  const auto make = [](int per_class, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> along(0.05F, 1.0F);
    std::normal_distribution<float> jitter(0.0F, 0.02F);
    Eigen::MatrixXf x(2, 3 * per_class);
    std::vector<int> classes;
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < per_class; ++i) {
        const float r = along(random);
        const float angle = 2.0F * std::numbers::pi_v<float> * (static_cast<float>(k) / 3.0F + 0.75F * r);
        const auto column = static_cast<Eigen::Index>(classes.size());
        x(0, column) = r * std::cos(angle) + jitter(random);
        x(1, column) = r * std::sin(angle) + jitter(random);
        classes.push_back(k);
      }
    }
    return std::pair{x, OneHot(classes, 3)};
  };
  const auto [train_x, train_y] = make(300, 1);
  const auto [test_x, test_y] = make(200, 2);
  Mlp net =
      Mlp::Random(std::array{2, 48, 48, 3}, std::array{Activation::kRelu, Activation::kRelu, Activation::kSoftmax}, 5);
  TrainingOptions options;
  options.loss = Loss::kCrossEntropy;
  options.adam.learning_rate = 5e-3F;
  options.seed = 9;
  MlpTrainer trainer(net, options);
  EXPECT_LT(Accuracy(net, test_x, test_y), 0.6);
  for (int epoch = 0; epoch < 200; ++epoch) trainer.Epoch(train_x, train_y);
  EXPECT_GT(Accuracy(net, test_x, test_y), 0.95);
  EXPECT_LT(Evaluate(net, Loss::kCrossEntropy, test_x, test_y), 0.2);
}

TEST(MlpTrainingTest, TheSameSeedTrainsTheSameWeightsBitForBit) {
  const Eigen::MatrixXf x = Normal(6, 200, 1);
  const Eigen::MatrixXf y = Normal(2, 200, 2);
  const auto train = [&](std::uint64_t order_seed) {
    Mlp net = Mlp::Random(std::array{6, 16, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 3);
    TrainingOptions options;
    options.seed = order_seed;
    MlpTrainer trainer(net, options);
    for (int epoch = 0; epoch < 5; ++epoch) trainer.Epoch(x, y);
    return net;
  };
  const Mlp a = train(1);
  const Mlp b = train(1);
  const Mlp c = train(2);
  for (std::size_t l = 0; l < a.layers().size(); ++l) {
    EXPECT_EQ(a.layers()[l].weights, b.layers()[l].weights);
    EXPECT_EQ(a.layers()[l].bias, b.layers()[l].bias);
  }
  EXPECT_NE(a.layers()[0].weights, c.layers()[0].weights);  // another order of the examples, other weights
}

TEST(MlpTrainingTest, RefusesWhatCannotTrain) {
  Mlp regression = Mlp::Random(std::array{3, 4, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 1);
  Mlp classifier = Mlp::Random(std::array{3, 4, 2}, std::array{Activation::kRelu, Activation::kSoftmax}, 1);
  TrainingOptions cross_entropy;
  cross_entropy.loss = Loss::kCrossEntropy;
  EXPECT_THROW(MlpTrainer(regression, cross_entropy), std::invalid_argument);
  EXPECT_THROW(MlpTrainer(classifier, TrainingOptions{}), std::invalid_argument);
  TrainingOptions no_batch;
  no_batch.batch = 0;
  EXPECT_THROW(MlpTrainer(regression, no_batch), std::invalid_argument);
  TrainingOptions no_rate;
  no_rate.adam.learning_rate = 0.0F;
  EXPECT_THROW(MlpTrainer(regression, no_rate), std::invalid_argument);
  MlpTrainer trainer(regression, TrainingOptions{});
  EXPECT_THROW(trainer.Step(Eigen::MatrixXf::Zero(4, 5), Eigen::MatrixXf::Zero(2, 5)), std::invalid_argument);
  EXPECT_THROW(trainer.Step(Eigen::MatrixXf::Zero(3, 5), Eigen::MatrixXf::Zero(2, 4)), std::invalid_argument);
  EXPECT_THROW(trainer.Step(Eigen::MatrixXf::Zero(3, 0), Eigen::MatrixXf::Zero(2, 0)), std::invalid_argument);
  EXPECT_EQ(trainer.Epoch(Eigen::MatrixXf::Zero(3, 0), Eigen::MatrixXf::Zero(2, 0)), 0.0);
}

}  // namespace
}  // namespace corridor::nav
