// The robot's poses of the last second, each with its time, for looking one up at another time: filled on a
// publisher's thread (a bus tap, so that a node's thread is not woken 50 times a second for them) and read on a node's
// executor, under one mutex. Held by shared_ptr where a tap fills it: the tap may outlive the node.
#pragma once

#include <deque>
#include <limits>
#include <mutex>
#include <optional>

#include "drivers/clock.h"
#include "nav/geometry/pose2.h"

namespace corridor::server {

class PoseHistory {
 public:
  static constexpr drivers::TimeNs kAnyGap = std::numeric_limits<drivers::TimeNs>::max();

  PoseHistory() = default;
  PoseHistory(const PoseHistory&) = delete;
  PoseHistory& operator=(const PoseHistory&) = delete;

  // A pose at `stamp_ns` (stamps in order); those more than a second older than it are dropped (two are kept).
  void Add(drivers::TimeNs stamp_ns, const nav::Pose2& pose);
  // The pose at `stamp_ns`, interpolated between the two around it; before the first or after the last, that one
  // when it is at most `max_gap_ns` away. nullopt otherwise, and before any.
  std::optional<nav::Pose2> At(drivers::TimeNs stamp_ns, drivers::TimeNs max_gap_ns = kAnyGap) const;
  // The last pose added; nullopt before any.
  std::optional<nav::Pose2> Latest() const;

 private:
  struct Stamped {
    drivers::TimeNs stamp_ns;
    nav::Pose2 pose;
  };
  mutable std::mutex mutex_;
  std::deque<Stamped> poses_;
};

}  // namespace corridor::server
