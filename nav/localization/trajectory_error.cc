#include "nav/localization/trajectory_error.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {
namespace {

class Accumulator {
 public:
  void Add(double v) {
    ++n_;
    sum_ += v;
    sum_sq_ += v * v;
    max_ = std::max(max_, v);
  }
  ErrorStats Stats() const {
    ErrorStats s;
    s.count = n_;
    if (n_ == 0) return s;
    s.mean = sum_ / n_;
    s.std = std::sqrt(std::max(0.0, sum_sq_ / n_ - s.mean * s.mean));
    s.max = max_;
    s.rmse = std::sqrt(sum_sq_ / n_);
    return s;
  }

 private:
  long n_ = 0;
  double sum_ = 0.0;
  double sum_sq_ = 0.0;
  double max_ = 0.0;
};

struct PairErrors {
  Accumulator translation;
  Accumulator rotation;
  void Add(const Pose2& truth_rel, const Pose2& estimate_rel) {
    const Pose2 e = truth_rel.Inverse() * estimate_rel;
    translation.Add(e.translation().norm());
    rotation.Add(std::abs(e.yaw_rad) * 180.0 / std::numbers::pi);
  }
  RelativeError Result() const { return {translation.Stats(), rotation.Stats()}; }
};

void RequireSameLength(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate) {
  if (truth.size() != estimate.size()) {
    throw std::invalid_argument("trajectory error: " + std::to_string(truth.size()) + " true poses against " +
                                std::to_string(estimate.size()) + " estimated");
  }
}

std::vector<double> Travel(const std::vector<Pose2>& truth) {
  std::vector<double> travel(truth.size(), 0.0);
  for (std::size_t i = 1; i < truth.size(); ++i) {
    travel[i] = travel[i - 1] + (truth[i].translation() - truth[i - 1].translation()).norm();
  }
  return travel;
}

}  // namespace

RelativeError LocalRelativeError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate,
                                 double max_travel_m) {
  RequireSameLength(truth, estimate);
  const std::vector<double> travel = Travel(truth);
  PairErrors errors;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (std::size_t j = i + 1; j < truth.size() && travel[j] - travel[i] <= max_travel_m; ++j) {
      errors.Add(truth[i].Inverse() * truth[j], estimate[i].Inverse() * estimate[j]);
    }
  }
  return errors.Result();
}

RelativeError RevisitRelativeError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate, double radius_m,
                                   double min_travel_m) {
  RequireSameLength(truth, estimate);
  const std::vector<double> travel = Travel(truth);
  PairErrors errors;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (std::size_t j = i + 1; j < truth.size(); ++j) {
      if (travel[j] - travel[i] < min_travel_m) continue;
      if ((truth[i].translation() - truth[j].translation()).norm() > radius_m) continue;
      errors.Add(truth[i].Inverse() * truth[j], estimate[i].Inverse() * estimate[j]);
    }
  }
  return errors.Result();
}

RelativeError AbsoluteError(const std::vector<Pose2>& truth, const std::vector<Pose2>& estimate) {
  RequireSameLength(truth, estimate);
  PairErrors errors;
  for (std::size_t i = 0; i < truth.size(); ++i) errors.Add(truth[i], estimate[i]);
  return errors.Result();
}

}  // namespace corridor::nav
