#include "nav/learning/dpoom_demonstrations.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace corridor::nav {
namespace {

constexpr int kLanes = 7;
constexpr int kStepInputs = kLanes + 2 + 3;  // dead-ends, the command, the goal's x and y, the yaw
constexpr double kFreeLane = 360.0;          // MORP's value for a lane free as far as it looks

}  // namespace

std::vector<DpoomRow> ReadDpoomDemonstration(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw DemonstrationFileError(path.string() + ": cannot open");
  std::string line;
  if (!std::getline(in, line) || line.rfind("time,", 0) != 0) {
    throw DemonstrationFileError(path.string() + ": line 1: want the header 'time,goal_x,...'");
  }
  std::vector<DpoomRow> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    std::istringstream fields(line);
    std::array<double, 13> v{};
    std::size_t n = 0;
    for (std::string field; n < v.size() && std::getline(fields, field, ',');) {
      try {
        std::size_t used = 0;
        v[n] = std::stod(field, &used);
        if (used == 0 || !std::isfinite(v[n])) throw std::invalid_argument(field);
      } catch (const std::exception&) {
        throw DemonstrationFileError(path.string() + ": line " + std::to_string(number) + ": '" + field +
                                     "' is not a number");
      }
      ++n;
    }
    std::string rest;
    if (n != v.size() || std::getline(fields, rest, ',')) {
      throw DemonstrationFileError(path.string() + ": line " + std::to_string(number) + ": want 13 numbers");
    }
    DpoomRow row{v[0], v[1], v[2], v[3], v[4], v[5], {}};
    for (int lane = 0; lane < kLanes; ++lane) row.deadends[static_cast<std::size_t>(lane)] = v[6 + lane];
    rows.push_back(row);
  }
  return rows;
}

Examples DpoomExamples(std::span<const DpoomRow> all_rows, int history, int skip) {
  if (history < 1) throw std::invalid_argument("a history of " + std::to_string(history) + " steps");
  const std::span<const DpoomRow> rows = all_rows.size() > static_cast<std::size_t>(skip)
                                             ? all_rows.subspan(static_cast<std::size_t>(skip))
                                             : std::span<const DpoomRow>{};
  const auto h = static_cast<std::size_t>(history);
  Examples examples;
  const std::size_t count = rows.size() >= 2 * h ? rows.size() - 2 * h + 1 : 0;
  examples.inputs.resize(history * kStepInputs, static_cast<Eigen::Index>(count));
  examples.targets.resize(2, static_cast<Eigen::Index>(count));
  for (std::size_t e = 0; e < count; ++e) {
    const std::size_t newest = e + h - 1;
    auto column = examples.inputs.col(static_cast<Eigen::Index>(e));
    Eigen::Index k = 0;
    for (std::size_t s = 0; s < h; ++s) {
      for (const double d : rows[newest + 1 - h + s].deadends) column(k++) = static_cast<float>(d / kFreeLane);
    }
    for (std::size_t s = 0; s < h; ++s) {
      column(k++) = static_cast<float>(rows[newest + 1 - h + s].linear_mps);
      column(k++) = static_cast<float>(rows[newest + 1 - h + s].angular_rps);
    }
    for (std::size_t s = 0; s < h; ++s) column(k++) = static_cast<float>(rows[newest + 1 - h + s].goal_x_m);
    for (std::size_t s = 0; s < h; ++s) column(k++) = static_cast<float>(rows[newest + 1 - h + s].goal_y_m);
    for (std::size_t s = 0; s < h; ++s) column(k++) = static_cast<float>(rows[newest + 1 - h + s].yaw_rad);
    examples.targets(0, static_cast<Eigen::Index>(e)) = static_cast<float>(rows[newest + 1].linear_mps);
    examples.targets(1, static_cast<Eigen::Index>(e)) = static_cast<float>(rows[newest + 1].angular_rps);
  }
  return examples;
}

Mlp DpoomNetwork(int inputs, std::uint64_t seed) {
  return Mlp::Random(
      std::array{inputs, inputs, 2 * inputs, 3 * inputs, inputs, 2},
      std::array{Activation::kRelu, Activation::kRelu, Activation::kRelu, Activation::kRelu, Activation::kIdentity},
      seed);
}

double RepeatLastCommandRmse(const Examples& examples, int history) {
  if (examples.size() == 0) return 0.0;
  const Eigen::Index last_command = static_cast<Eigen::Index>(history) * kLanes + 2 * (history - 1);
  const Eigen::MatrixXf last = examples.inputs.middleRows(last_command, 2);
  return std::sqrt((last - examples.targets).squaredNorm() / static_cast<double>(examples.targets.size()));
}

}  // namespace corridor::nav
