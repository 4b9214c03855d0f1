// Percentiles of a latency over the last samples, and the rate at which they come: for the control loop's
// frame-to-command latency. Not thread-safe: one owner records and summarises.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drivers/clock.h"

namespace corridor::server {

class LatencyStats {
 public:
  struct Summary {
    double rate_hz = 0.0;  // samples per second over the last rate window
    double p50_ms = 0.0;
    double p99_ms = 0.0;
    double max_ms = 0.0;
    std::uint64_t samples = 0;  // since start
  };

  explicit LatencyStats(std::size_t window = 1000) : window_(window) { recent_.reserve(window); }

  void Record(drivers::TimeNs now_ns, double latency_ms) {
    if (recent_.size() < window_) {
      recent_.push_back(latency_ms);
    } else {
      recent_[next_] = latency_ms;
    }
    next_ = (next_ + 1) % window_;
    ++samples_;
    if (rate_begin_ns_ < 0) rate_begin_ns_ = now_ns;
    ++rate_count_;
  }

  // Percentiles over the last `window` samples; the rate since the previous Summarise.
  Summary Summarise(drivers::TimeNs now_ns) {
    Summary s;
    s.samples = samples_;
    if (rate_begin_ns_ >= 0 && now_ns > rate_begin_ns_) {
      s.rate_hz = static_cast<double>(rate_count_) / drivers::ToSeconds(now_ns - rate_begin_ns_);
    }
    rate_begin_ns_ = now_ns;
    rate_count_ = 0;
    if (recent_.empty()) return s;
    std::vector<double> sorted = recent_;
    std::sort(sorted.begin(), sorted.end());
    const auto at = [&](double q) {
      return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
    };
    s.p50_ms = at(0.5);
    s.p99_ms = at(0.99);
    s.max_ms = sorted.back();
    return s;
  }

 private:
  std::size_t window_;
  std::vector<double> recent_;
  std::size_t next_ = 0;
  std::uint64_t samples_ = 0;
  drivers::TimeNs rate_begin_ns_ = -1;
  std::uint64_t rate_count_ = 0;
};

}  // namespace corridor::server
