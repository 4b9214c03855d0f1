// A small fully connected network (multi-layer perceptron) for the learned local policies: dense layers with ReLU,
// tanh, sigmoid or softmax, in single precision with Eigen. Why written here rather than taken from a library (mlpack
// and ONNX Runtime are not in Debian 12; libtorch is 131 MB; OpenCV's ANN_MLP has one activation for all layers and
// no Adam or softmax): docs/policies.md. OpenCV's dnn module, built from the same weights, checks the forward pass in
// the tests.
//
// Weights file (docs/policies.md, "Weights files"): a text header, then the numbers as raw little-endian float32:
//   corridor-mlp 1
//   layers N
//   dense IN OUT ACTIVATION        (N lines; ACTIVATION: identity, relu, tanh, sigmoid, softmax)
//   data
//   <for each layer: OUT x IN weights, row by row, then OUT biases>
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace corridor::nav {

enum class Activation { kIdentity, kRelu, kTanh, kSigmoid, kSoftmax };

// "relu", "tanh", ...; ParseActivation throws std::invalid_argument naming what it got.
std::string_view ActivationName(Activation activation);
Activation ParseActivation(std::string_view name);

// y = activation(weights * x + bias): weights are outputs x inputs.
struct DenseLayer {
  Eigen::MatrixXf weights;
  Eigen::VectorXf bias;
  Activation activation = Activation::kIdentity;
};

// A weights file that cannot be read: names the file (or "stream") and what was wrong.
class MlpFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Mlp {
 public:
  Mlp() = default;
  // Throws std::invalid_argument when a layer's inputs are not the previous layer's outputs, a bias does not match its
  // weights, a layer is empty, or a softmax is not the last layer.
  explicit Mlp(std::vector<DenseLayer> layers);

  // A network of layers sizes[0] -> sizes[1] -> ... with activations[i] after layer i (one fewer activations than
  // sizes), initialised as PyTorch's nn.Linear does (weights and biases uniform in +-1/sqrt(inputs)) from `seed`: the
  // same seed gives the same weights, bit for bit. Throws std::invalid_argument for sizes below 1 or a count mismatch.
  static Mlp Random(std::span<const int> sizes, std::span<const Activation> activations, std::uint64_t seed);

  int inputs() const;
  int outputs() const;
  bool empty() const { return layers_.empty(); }
  const std::vector<DenseLayer>& layers() const { return layers_; }
  std::vector<DenseLayer>& layers() { return layers_; }  // for training: shapes must stay as they are
  std::size_t parameter_count() const;

  // The network's output for one input (size inputs(); checked, std::invalid_argument otherwise).
  Eigen::VectorXf Forward(const Eigen::Ref<const Eigen::VectorXf>& input) const;
  // For many inputs at once, one per column.
  Eigen::MatrixXf ForwardBatch(const Eigen::Ref<const Eigen::MatrixXf>& inputs) const;

  // The weights file above. Save throws std::runtime_error when the file cannot be written; Load throws
  // MlpFormatError for a file that is missing, truncated, has a bad header or sizes that do not chain.
  void Save(std::ostream& out) const;
  void Save(const std::filesystem::path& path) const;
  static Mlp Load(std::istream& in, std::string_view what = "stream");
  static Mlp Load(const std::filesystem::path& path);

 private:
  std::vector<DenseLayer> layers_;
};

// Applies `activation` to each column of `z` in place (softmax over each column).
void Activate(Activation activation, Eigen::Ref<Eigen::MatrixXf> z);

}  // namespace corridor::nav
