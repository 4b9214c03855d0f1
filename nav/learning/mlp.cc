#include "nav/learning/mlp.h"

#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <istream>
#include <ostream>
#include <random>
#include <sstream>
#include <system_error>
#include <utility>

namespace corridor::nav {
namespace {

static_assert(std::endian::native == std::endian::little, "weights files are little-endian float32, read as is");

constexpr std::string_view kMagic = "corridor-mlp 1";
constexpr std::array<std::pair<Activation, std::string_view>, 5> kActivationNames{{
    {Activation::kIdentity, "identity"},
    {Activation::kRelu, "relu"},
    {Activation::kTanh, "tanh"},
    {Activation::kSigmoid, "sigmoid"},
    {Activation::kSoftmax, "softmax"},
}};
// The parts of a message, written one after the other.
template <typename... Parts>
std::string Text(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

// One header line of at most kMaxLine characters (a longer one is not a weights file's: false, as at the end).
constexpr std::size_t kMaxLine = 200;
bool ReadLine(std::istream& in, std::string& line) {
  line.clear();
  for (int c = in.get(); c != std::istream::traits_type::eof(); c = in.get()) {
    if (c == '\n') return true;
    if (line.size() == kMaxLine) return false;
    line.push_back(static_cast<char>(c));
  }
  return !line.empty();
}

// A weights file larger than this is not a small policy network's.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{256} << 20U;

// Layers wider than this are not a small policy network: a header asking for more is a broken file.
constexpr int kMaxWidth = 1 << 16;

// Throws std::invalid_argument for layers that do not make a network (Mlp's constructor says which).
void CheckLayers(const std::vector<DenseLayer>& layers) {
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const DenseLayer& layer = layers[i];
    if (layer.weights.rows() < 1 || layer.weights.cols() < 1) {
      throw std::invalid_argument(Text("layer ", i, ": no weights"));
    }
    if (layer.bias.size() != layer.weights.rows()) {
      throw std::invalid_argument(
          Text("layer ", i, ": ", layer.bias.size(), " biases for ", layer.weights.rows(), " outputs"));
    }
    if (i > 0 && layer.weights.cols() != layers[i - 1].weights.rows()) {
      throw std::invalid_argument(Text("layer ", i, " takes ", layer.weights.cols(), " inputs but layer ", i - 1,
                                       " gives ", layers[i - 1].weights.rows()));
    }
    if (layer.activation == Activation::kSoftmax && i + 1 != layers.size()) {
      throw std::invalid_argument(Text("layer ", i, ": softmax only on the last layer"));
    }
  }
}

}  // namespace

std::string_view ActivationName(Activation activation) {
  for (const auto& [a, name] : kActivationNames) {
    if (a == activation) return name;
  }
  return "unknown";
}

Activation ParseActivation(std::string_view name) {
  for (const auto& [a, n] : kActivationNames) {
    if (n == name) return a;
  }
  throw std::invalid_argument(Text("unknown activation '", name, "' (identity, relu, tanh, sigmoid or softmax)"));
}

void Activate(Activation activation, Eigen::Ref<Eigen::MatrixXf> z) {
  switch (activation) {
    case Activation::kIdentity: return;
    case Activation::kRelu: z = z.cwiseMax(0.0F); return;
    case Activation::kTanh: z = z.array().tanh(); return;
    case Activation::kSigmoid: z = (1.0F + (-z.array()).exp()).inverse(); return;
    case Activation::kSoftmax:
      for (Eigen::Index c = 0; c < z.cols(); ++c) {
        auto column = z.col(c);
        column = (column.array() - column.maxCoeff()).exp();  // shifted: no overflow
        column /= column.sum();
      }
      return;
  }
}

Mlp::Mlp(std::vector<DenseLayer> layers) : layers_(std::move(layers)) { CheckLayers(layers_); }

Mlp Mlp::Random(std::span<const int> sizes, std::span<const Activation> activations, std::uint64_t seed) {
  if (sizes.size() < 2 || activations.size() + 1 != sizes.size()) {
    throw std::invalid_argument(Text(sizes.size(), " sizes and ", activations.size(),
                                     " activations: want at least two sizes and one activation per layer"));
  }
  for (const int size : sizes) {
    if (size < 1 || size > kMaxWidth) throw std::invalid_argument(Text("a layer of ", size, " units"));
  }
  std::mt19937_64 random(seed);
  // Uniform in [-bound, bound) from the generator's top 24 bits: the same numbers whatever the standard library.
  const auto uniform = [&](float bound) {
    const auto bits = static_cast<float>(random() >> 40U);
    return bound * (2.0F * bits / static_cast<float>(1U << 24U) - 1.0F);
  };
  std::vector<DenseLayer> layers;
  for (std::size_t i = 0; i + 1 < sizes.size(); ++i) {
    DenseLayer layer;
    const float bound = 1.0F / std::sqrt(static_cast<float>(sizes[i]));
    layer.weights.resize(sizes[i + 1], sizes[i]);
    for (Eigen::Index r = 0; r < layer.weights.rows(); ++r) {
      for (Eigen::Index c = 0; c < layer.weights.cols(); ++c) layer.weights(r, c) = uniform(bound);
    }
    layer.bias.resize(sizes[i + 1]);
    for (Eigen::Index r = 0; r < layer.bias.size(); ++r) layer.bias(r) = uniform(bound);
    layer.activation = activations[i];
    layers.push_back(std::move(layer));
  }
  return Mlp(std::move(layers));
}

int Mlp::inputs() const { return layers_.empty() ? 0 : static_cast<int>(layers_.front().weights.cols()); }

int Mlp::outputs() const { return layers_.empty() ? 0 : static_cast<int>(layers_.back().weights.rows()); }

std::size_t Mlp::parameter_count() const {
  std::size_t n = 0;
  for (const DenseLayer& layer : layers_) n += static_cast<std::size_t>(layer.weights.size() + layer.bias.size());
  return n;
}

Eigen::VectorXf Mlp::Forward(const Eigen::Ref<const Eigen::VectorXf>& input) const {
  if (input.size() != inputs()) {
    throw std::invalid_argument(Text(input.size(), " inputs for a network of ", inputs()));
  }
  Eigen::VectorXf x = input;
  for (const DenseLayer& layer : layers_) {
    Eigen::VectorXf z = layer.bias;
    z.noalias() += layer.weights * x;
    Activate(layer.activation, z);
    x = std::move(z);
  }
  return x;
}

Eigen::MatrixXf Mlp::ForwardBatch(const Eigen::Ref<const Eigen::MatrixXf>& inputs) const {
  if (inputs.rows() != this->inputs()) {
    throw std::invalid_argument(Text("inputs of ", inputs.rows(), " values for a network of ", this->inputs()));
  }
  Eigen::MatrixXf x = inputs;
  for (const DenseLayer& layer : layers_) {
    Eigen::MatrixXf z = layer.bias.replicate(1, x.cols());
    z.noalias() += layer.weights * x;
    Activate(layer.activation, z);
    x = std::move(z);
  }
  return x;
}

void Mlp::Save(std::ostream& out) const {
  out << kMagic << "\nlayers " << layers_.size() << '\n';
  for (const DenseLayer& layer : layers_) {
    out << "dense " << layer.weights.cols() << ' ' << layer.weights.rows() << ' ' << ActivationName(layer.activation)
        << '\n';
  }
  out << "data\n";
  for (const DenseLayer& layer : layers_) {
    // Row by row: Eigen keeps columns together, so the transpose's storage is the rows'.
    const Eigen::MatrixXf rows = layer.weights.transpose();
    out.write(reinterpret_cast<const char*>(rows.data()), static_cast<std::streamsize>(rows.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(layer.bias.data()),
              static_cast<std::streamsize>(layer.bias.size() * sizeof(float)));
  }
}

void Mlp::Save(const std::filesystem::path& path) const {
  std::ofstream out(path, std::ios::binary);
  Save(out);
  out.close();
  if (!out) throw std::runtime_error(Text(path.string(), ": cannot write the weights"));
}

Mlp Mlp::Load(std::istream& in, std::string_view what) {
  const auto fail = [&](const std::string& why) { return MlpFormatError(Text(what, ": ", why)); };
  std::string line;
  if (!ReadLine(in, line) || line != kMagic) throw fail(Text("not a weights file (want '", kMagic, "')"));
  std::size_t count = 0;
  {
    std::string word;
    if (!ReadLine(in, line) || !(std::istringstream(line) >> word >> count) || word != "layers" || count < 1 ||
        count > 64) {
      throw fail(Text("want 'layers N' (1 to 64), got '", line, "'"));
    }
  }
  std::vector<DenseLayer> layers(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::string word;
    std::string activation;
    int in_size = 0;
    int out_size = 0;
    if (!ReadLine(in, line) || !(std::istringstream(line) >> word >> in_size >> out_size >> activation) ||
        word != "dense" || in_size < 1 || out_size < 1 || in_size > kMaxWidth || out_size > kMaxWidth) {
      throw fail(Text("layer ", i, ": want 'dense IN OUT ACTIVATION', got '", line, "'"));
    }
    try {
      layers[i].activation = ParseActivation(activation);
    } catch (const std::invalid_argument& e) {
      throw fail(Text("layer ", i, ": ", e.what()));
    }
    layers[i].weights.resize(out_size, in_size);
    layers[i].bias.resize(out_size);
  }
  try {
    CheckLayers(layers);
  } catch (const std::invalid_argument& e) {
    throw fail(e.what());
  }
  if (!ReadLine(in, line) || line != "data") throw fail("no 'data' line after the layers");
  for (std::size_t i = 0; i < count; ++i) {
    DenseLayer& layer = layers[i];
    Eigen::MatrixXf rows(layer.weights.cols(), layer.weights.rows());
    in.read(reinterpret_cast<char*>(rows.data()), static_cast<std::streamsize>(rows.size() * sizeof(float)));
    in.read(reinterpret_cast<char*>(layer.bias.data()),
            static_cast<std::streamsize>(layer.bias.size() * sizeof(float)));
    if (!in) throw fail(Text("the numbers end in layer ", i));
    layer.weights = rows.transpose();
    if (!layer.weights.allFinite() || !layer.bias.allFinite()) throw fail(Text("layer ", i, ": not a number"));
  }
  if (in.peek() != std::istream::traits_type::eof()) throw fail("bytes after the last layer's numbers");
  return Mlp(std::move(layers));
}

Mlp Mlp::Load(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw MlpFormatError(Text(path.string(), ": cannot open the weights (not a file)"));
  }
  if (std::filesystem::file_size(path, error) > kMaxFileBytes) {
    throw MlpFormatError(
        Text(path.string(), ": larger than a policy network's weights (", kMaxFileBytes >> 20U, " MB at most)"));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MlpFormatError(Text(path.string(), ": cannot open the weights"));
  return Load(in, path.string());
}

}  // namespace corridor::nav
