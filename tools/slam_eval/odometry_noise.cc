#include "tools/slam_eval/odometry_noise.h"

#include <cmath>

namespace corridor::tools {

std::vector<nav::Pose2> MakeOdometry(const std::vector<nav::Pose2>& truth, const OdometryNoise& noise,
                                     std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<nav::Pose2> odometry;
  odometry.reserve(truth.size());
  if (truth.empty()) return odometry;
  odometry.push_back(truth.front());
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const nav::Pose2 step = truth[i - 1].Inverse() * truth[i];
    const double length = step.translation().norm();
    // The noise of a turn is proportional to the heading change; the direction of travel (the chord of the arc)
    // shares half of it. Below a millimetre the direction of travel means nothing.
    const double direction = length > 1e-3 ? std::atan2(step.y_m, step.x_m) : 0.0;
    const double turned = std::abs(step.yaw_rad);
    const double noisy_length = length * (1.0 + noise.scale_error + noise.translation_sigma * normal(random));
    const double noisy_direction = direction + 0.5 * noise.rotation_sigma * turned * normal(random);
    const double noisy_turn =
        step.yaw_rad + noise.rotation_sigma * turned * normal(random) + noise.heading_drift_rad_per_m * length;
    odometry.push_back(odometry.back() * nav::Pose2{noisy_length * std::cos(noisy_direction),
                                                    noisy_length * std::sin(noisy_direction), noisy_turn});
  }
  return odometry;
}

}  // namespace corridor::tools
