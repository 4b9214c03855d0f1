#include "nav/policy/morp_il.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace corridor::nav {

MorpIlFeatures::MorpIlFeatures(const MorpIlOptions& options) : options_(options) {
  if (options.history < 1 || options.history > 20 || !(options.lane_range_m > 0.0) || !(options.goal_range_m > 0.0) ||
      !(options.max_linear_mps > 0.0) || !(options.max_angular_rps > 0.0)) {
    throw std::invalid_argument(
        "MORP-IL: history from 1 to 20, and lane_range_m, goal_range_m and the speed limits positive");
  }
}

void MorpIlFeatures::Push(const std::vector<LaneResult>& lanes, double goal_bearing_rad, double goal_distance_m,
                          bool final_approach, const Twist2& last_command) {
  Eigen::Matrix<float, kMorpIlStepInputs, 1> step;
  // Each bin the nearest of its lanes (by index, left to right); no lanes: all blind.
  std::array<double, kMorpIlLaneBins> bins{};
  bins.fill(lanes.empty() ? 0.0 : 1.0);
  const std::size_t n = lanes.size();
  for (std::size_t i = 0; i < n; ++i) {
    const LaneResult& lane = lanes[i];
    const double free =
        lane.blind ? 0.0 : (lane.dead_end ? std::min(1.0, lane.free_distance_m / options_.lane_range_m) : 1.0);
    double& bin = bins[i * kMorpIlLaneBins / n];
    bin = std::min(bin, free);
  }
  for (int b = 0; b < kMorpIlLaneBins; ++b) step(b) = static_cast<float>(bins[static_cast<std::size_t>(b)]);
  step(7) = static_cast<float>(std::clamp(last_command.linear_mps / options_.max_linear_mps, -1.0, 1.0));
  step(8) = static_cast<float>(std::clamp(last_command.angular_rps / options_.max_angular_rps, -1.0, 1.0));
  step(9) = static_cast<float>(WrapAngle(goal_bearing_rad) / std::numbers::pi);
  step(10) = static_cast<float>(std::min(1.0, std::max(0.0, goal_distance_m) / options_.goal_range_m));
  step(11) = final_approach ? 1.0F : 0.0F;
  steps_.push_back(step);
  while (static_cast<int>(steps_.size()) > options_.history) steps_.pop_front();
}

Eigen::VectorXf MorpIlFeatures::Input() const {
  Eigen::VectorXf input = Eigen::VectorXf::Zero(size());
  if (steps_.empty()) return input;
  const int missing = options_.history - static_cast<int>(steps_.size());
  for (int s = 0; s < options_.history; ++s) {
    input.segment<kMorpIlStepInputs>(s * kMorpIlStepInputs) =
        steps_[static_cast<std::size_t>(std::max(0, s - missing))];
  }
  return input;
}

void CheckMorpIlNetwork(const Mlp& net, const MorpIlOptions& options) {
  if (net.inputs() != options.history * kMorpIlStepInputs || net.outputs() != 2) {
    throw std::invalid_argument("MORP-IL: a network of " + std::to_string(net.inputs()) + " inputs and " +
                                std::to_string(net.outputs()) + " outputs; want " +
                                std::to_string(options.history * kMorpIlStepInputs) + " (history " +
                                std::to_string(options.history) + ") and 2");
  }
}

Twist2 MorpIlCommand(const Mlp& net, const Eigen::VectorXf& input, const MorpIlOptions& options) {
  const Eigen::VectorXf out = net.Forward(input);
  const auto scaled = [](float value, double limit) {
    return std::isfinite(value) ? std::clamp(static_cast<double>(value), -1.0, 1.0) * limit : 0.0;
  };
  return {scaled(out(0), options.max_linear_mps), scaled(out(1), options.max_angular_rps)};
}

}  // namespace corridor::nav
