#include "server/nodes/pose_history.h"

#include <algorithm>
#include <iterator>

namespace corridor::server {
namespace {

constexpr drivers::TimeNs kKeptNs = 1'000'000'000;

}  // namespace

void PoseHistory::Add(drivers::TimeNs stamp_ns, const nav::Pose2& pose) {
  std::lock_guard lock(mutex_);
  poses_.push_back({stamp_ns, pose});
  while (poses_.size() > 2 && stamp_ns - poses_.front().stamp_ns > kKeptNs) poses_.pop_front();
}

std::optional<nav::Pose2> PoseHistory::At(drivers::TimeNs stamp_ns, drivers::TimeNs max_gap_ns) const {
  std::lock_guard lock(mutex_);
  if (poses_.empty()) return std::nullopt;
  const auto after = std::lower_bound(poses_.begin(), poses_.end(), stamp_ns,
                                      [](const Stamped& p, drivers::TimeNs t) { return p.stamp_ns < t; });
  if (after == poses_.end()) {
    if (stamp_ns - poses_.back().stamp_ns > max_gap_ns) return std::nullopt;
    return poses_.back().pose;
  }
  if (after == poses_.begin()) {
    if (after->stamp_ns - stamp_ns > max_gap_ns) return std::nullopt;
    return after->pose;
  }
  const auto before = std::prev(after);
  const double f = static_cast<double>(stamp_ns - before->stamp_ns) /
                   static_cast<double>(std::max<drivers::TimeNs>(1, after->stamp_ns - before->stamp_ns));
  return nav::Interpolate(before->pose, after->pose, f);
}

std::optional<nav::Pose2> PoseHistory::Latest() const {
  std::lock_guard lock(mutex_);
  if (poses_.empty()) return std::nullopt;
  return poses_.back().pose;
}

}  // namespace corridor::server
