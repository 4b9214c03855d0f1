// Where a pan servo was at a time: the readings it reported (its driver's, about every 20 ms), interpolated to a
// camera frame's stamp, so that each frame is read with the camera's pose when it was taken. None when the servo's
// angle at that time is not known well: no reading within max_gap_s on either side (the servo silent, or the frame
// older than the history), in which case the frame must not be used.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>

namespace corridor::nav {

class PanHistory {
 public:
  explicit PanHistory(double max_gap_s = 0.1, std::size_t capacity = 100)
      : max_gap_s_(max_gap_s), capacity_(capacity) {}

  // A reading at t_s (seconds; readings come in time order, an older one is ignored), with the servo's velocity.
  void Add(double t_s, double pan_rad, double velocity_rps) {
    if (!readings_.empty() && t_s <= readings_.back().t_s) return;
    readings_.push_back({t_s, pan_rad, velocity_rps});
    if (readings_.size() > capacity_) readings_.pop_front();
  }

  // The angle at t_s: between two readings, on the line between them (when they are at most 2 max_gap_s apart);
  // within max_gap_s after the newest, carried on at its velocity; else none.
  std::optional<double> At(double t_s) const {
    if (readings_.empty() || t_s < readings_.front().t_s - 1e-9) return std::nullopt;
    const Reading& newest = readings_.back();
    if (t_s >= newest.t_s) {
      if (t_s - newest.t_s > max_gap_s_) return std::nullopt;
      return newest.pan_rad + newest.velocity_rps * (t_s - newest.t_s);
    }
    std::size_t i = readings_.size() - 1;
    while (readings_[i - 1].t_s > t_s) --i;  // readings_[i - 1].t_s <= t_s < readings_[i].t_s
    const Reading& a = readings_[i - 1];
    const Reading& b = readings_[i];
    if (b.t_s - a.t_s > 2.0 * max_gap_s_) return std::nullopt;
    return a.pan_rad + (b.pan_rad - a.pan_rad) * (t_s - a.t_s) / (b.t_s - a.t_s);
  }

  bool empty() const { return readings_.empty(); }

 private:
  struct Reading {
    double t_s;
    double pan_rad;
    double velocity_rps;
  };
  double max_gap_s_;
  std::size_t capacity_;
  std::deque<Reading> readings_;
};

}  // namespace corridor::nav
