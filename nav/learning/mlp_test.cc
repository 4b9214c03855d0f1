#include "nav/learning/mlp.h"

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include "testing/opencv_mlp.h"

namespace corridor::nav {
namespace {

using ::testing::HasSubstr;

TEST(MlpTest, ForwardAgreesWithOpenCvDnnForEveryActivation) {
  // Random networks (seeded) of each activation, on random inputs: corridor's forward pass and OpenCV's agree.
  const std::array<std::vector<Activation>, 4> shapes{{
      {Activation::kRelu, Activation::kRelu, Activation::kIdentity},
      {Activation::kTanh, Activation::kSigmoid, Activation::kSoftmax},
      {Activation::kSigmoid, Activation::kTanh, Activation::kTanh},
      {Activation::kRelu, Activation::kTanh, Activation::kSoftmax},
  }};
  std::mt19937 random(11);
  std::normal_distribution<float> normal(0.0F, 1.5F);
  const std::array<int, 4> sizes{48, 96, 144, 20};
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const Mlp mlp = Mlp::Random(sizes, shapes[s], 100 + s);
    cv::dnn::Net net = testing::OpenCvMlp(mlp);
    Eigen::MatrixXf inputs(sizes.front(), 16);
    for (Eigen::Index i = 0; i < inputs.size(); ++i) inputs(i) = normal(random);
    const Eigen::MatrixXf batch = mlp.ForwardBatch(inputs);
    for (Eigen::Index c = 0; c < inputs.cols(); ++c) {
      cv::Mat blob(1, sizes.front(), CV_32F);
      for (int i = 0; i < blob.cols; ++i) blob.at<float>(0, i) = inputs(i, c);
      net.setInput(blob);
      const cv::Mat theirs = net.forward();
      const Eigen::VectorXf ours = mlp.Forward(Eigen::VectorXf(inputs.col(c)));
      ASSERT_EQ(theirs.total(), static_cast<std::size_t>(ours.size()));
      for (Eigen::Index o = 0; o < ours.size(); ++o) {
        EXPECT_NEAR(ours(o), theirs.at<float>(static_cast<int>(o)), 1e-5F + 1e-5F * std::abs(ours(o)))
            << "shape " << s << ", input " << c << ", output " << o;
        EXPECT_NEAR(batch(o, c), ours(o), 1e-5F + 1e-5F * std::abs(ours(o)));  // one at a time or many at once
      }
    }
  }
}

TEST(MlpTest, SoftmaxGivesProbabilitiesEvenForHugeInputs) {
  Eigen::MatrixXf z(3, 2);
  z << 1000.0F, -5.0F, 1000.0F, 0.0F, -1000.0F, 5.0F;
  Activate(Activation::kSoftmax, z);
  EXPECT_TRUE(z.allFinite());
  EXPECT_NEAR(z(0, 0), 0.5F, 1e-6F);
  EXPECT_NEAR(z(2, 0), 0.0F, 1e-6F);
  EXPECT_NEAR(z.col(1).sum(), 1.0F, 1e-6F);
  EXPECT_GT(z(2, 1), z(1, 1));
}

TEST(MlpTest, InitialisationIsTheSeedsAndPyTorchsBounds) {
  const std::array<int, 3> sizes{25, 64, 4};
  const std::array<Activation, 2> activations{Activation::kRelu, Activation::kIdentity};
  const Mlp a = Mlp::Random(sizes, activations, 7);
  const Mlp b = Mlp::Random(sizes, activations, 7);
  const Mlp c = Mlp::Random(sizes, activations, 8);
  EXPECT_EQ(a.layers()[0].weights, b.layers()[0].weights);
  EXPECT_EQ(a.layers()[1].bias, b.layers()[1].bias);
  EXPECT_NE(a.layers()[0].weights, c.layers()[0].weights);
  // nn.Linear's bounds, 1/sqrt(inputs), filled: not all near zero nor outside.
  EXPECT_LE(a.layers()[0].weights.cwiseAbs().maxCoeff(), 0.2F);
  EXPECT_GT(a.layers()[0].weights.cwiseAbs().maxCoeff(), 0.19F);
  EXPECT_LE(a.layers()[1].weights.cwiseAbs().maxCoeff(), 0.125F);
  EXPECT_NEAR(a.layers()[0].weights.mean(), 0.0F, 0.01F);
  EXPECT_EQ(a.parameter_count(), 25U * 64U + 64U + 64U * 4U + 4U);
}

TEST(MlpTest, RefusesLayersThatDoNotChain) {
  const auto layer = [](int in, int out, Activation a = Activation::kRelu) {
    return DenseLayer{Eigen::MatrixXf::Zero(out, in), Eigen::VectorXf::Zero(out), a};
  };
  EXPECT_THROW(Mlp({layer(4, 8), layer(7, 2)}), std::invalid_argument);
  EXPECT_THROW(Mlp({DenseLayer{Eigen::MatrixXf::Zero(3, 2), Eigen::VectorXf::Zero(2), Activation::kRelu}}),
               std::invalid_argument);
  EXPECT_THROW(Mlp({layer(4, 8, Activation::kSoftmax), layer(8, 2)}), std::invalid_argument);
  EXPECT_THROW(Mlp::Random(std::array{4}, std::array<Activation, 0>{}, 1), std::invalid_argument);
  EXPECT_THROW(Mlp::Random(std::array{4, 0}, std::array{Activation::kRelu}, 1), std::invalid_argument);
  const Mlp mlp({layer(4, 8), layer(8, 2)});
  EXPECT_THROW(mlp.Forward(Eigen::VectorXf(Eigen::VectorXf::Zero(5))), std::invalid_argument);
  EXPECT_THROW(mlp.ForwardBatch(Eigen::MatrixXf::Zero(3, 10)), std::invalid_argument);
  EXPECT_THROW(ParseActivation("gelu"), std::invalid_argument);
}

TEST(MlpTest, WeightsFileRoundTripsBitForBit) {
  const Mlp mlp = Mlp::Random(std::array{10, 16, 3}, std::array{Activation::kTanh, Activation::kSoftmax}, 3);
  const auto path = std::filesystem::temp_directory_path() / "corridor-mlp-test.weights";
  mlp.Save(path);
  const Mlp back = Mlp::Load(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.layers().size(), 2U);
  for (std::size_t l = 0; l < 2; ++l) {
    EXPECT_EQ(back.layers()[l].weights, mlp.layers()[l].weights);
    EXPECT_EQ(back.layers()[l].bias, mlp.layers()[l].bias);
    EXPECT_EQ(back.layers()[l].activation, mlp.layers()[l].activation);
  }
  std::ostringstream text;
  mlp.Save(text);
  const std::string header = "corridor-mlp 1\nlayers 2\ndense 10 16 tanh\ndense 16 3 softmax\ndata\n";
  EXPECT_EQ(text.str().substr(0, header.size()), header);
  EXPECT_EQ(text.str().size(), header.size() + sizeof(float) * mlp.parameter_count());
  // The first number is the first layer's first row's first weight, then the rest of that row.
  float first[2];
  std::memcpy(first, text.str().data() + header.size(), sizeof(first));
  EXPECT_EQ(first[0], mlp.layers()[0].weights(0, 0));
  EXPECT_EQ(first[1], mlp.layers()[0].weights(0, 1));
}

TEST(MlpTest, BrokenWeightsFilesAreRefusedSayingWhy) {
  const Mlp mlp = Mlp::Random(std::array{4, 6, 2}, std::array{Activation::kRelu, Activation::kIdentity}, 5);
  std::ostringstream out;
  mlp.Save(out);
  const std::string good = out.str();
  const auto load = [](const std::string& bytes) {
    std::istringstream in(bytes);
    return Mlp::Load(in, "policy.weights");
  };
  const auto refusal = [&](const std::string& bytes) {
    try {
      load(bytes);
    } catch (const MlpFormatError& e) {
      return std::string(e.what());
    }
    return std::string("(loaded)");
  };
  EXPECT_NO_THROW(load(good));
  EXPECT_THAT(refusal(""), HasSubstr("policy.weights: not a weights file"));
  EXPECT_THAT(refusal("PK\x03\x04 a zip"), HasSubstr("not a weights file"));
  EXPECT_THAT(refusal(good.substr(0, good.size() - 3)), HasSubstr("the numbers end in layer 1"));
  EXPECT_THAT(refusal(good + "x"), HasSubstr("bytes after the last layer"));
  std::string bad_activation = good;
  bad_activation.replace(bad_activation.find("relu"), 4, "gelu");
  EXPECT_THAT(refusal(bad_activation), HasSubstr("layer 0: unknown activation 'gelu'"));
  std::string bad_chain = good;
  bad_chain.replace(bad_chain.find("dense 6 2"), 9, "dense 5 2");
  EXPECT_THAT(refusal(bad_chain), HasSubstr("layer 1 takes 5 inputs but layer 0 gives 6"));
  std::string huge = good;
  huge.replace(huge.find("dense 4 6"), 9, "dense 4 999999999");
  EXPECT_THAT(refusal(huge), HasSubstr("want 'dense IN OUT ACTIVATION'"));
  std::string not_a_number = good;
  const float nan = std::nanf("");
  not_a_number.replace(good.find("data\n") + 5, sizeof(float), reinterpret_cast<const char*>(&nan), sizeof(float));
  EXPECT_THAT(refusal(not_a_number), HasSubstr("layer 0: not a number"));
  EXPECT_THAT(refusal(std::string(100000, 'x')), HasSubstr("not a weights file"));  // one endless line
  EXPECT_THROW(Mlp::Load(std::filesystem::path("/nonexistent/policy.weights")), MlpFormatError);
  // Not a file: a device that never ends, a directory.
  EXPECT_THROW(Mlp::Load(std::filesystem::path("/dev/zero")), MlpFormatError);
  EXPECT_THROW(Mlp::Load(std::filesystem::temp_directory_path()), MlpFormatError);
}

}  // namespace
}  // namespace corridor::nav
