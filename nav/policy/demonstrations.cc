#include "nav/policy/demonstrations.h"

namespace corridor::nav {

Examples Demonstrations::Take(int input_size) {
  Examples taken;
  const auto count = static_cast<Eigen::Index>(inputs.size() / static_cast<std::size_t>(input_size));
  taken.inputs = Eigen::Map<const Eigen::MatrixXf>(inputs.data(), input_size, count);
  const auto outputs = count == 0 ? Eigen::Index{0} : static_cast<Eigen::Index>(targets.size()) / count;
  taken.targets = Eigen::Map<const Eigen::MatrixXf>(targets.data(), outputs, count);
  inputs.clear();
  targets.clear();
  return taken;
}

}  // namespace corridor::nav
