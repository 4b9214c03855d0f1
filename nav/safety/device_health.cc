#include "nav/safety/device_health.h"

#include <algorithm>
#include <stdexcept>

namespace corridor::nav {

const char* ToString(DeviceState state) {
  switch (state) {
    case DeviceState::kOk: return "ok";
    case DeviceState::kStale: return "stale";
    case DeviceState::kDisconnected: return "disconnected";
  }
  return "unknown";
}

DeviceWatch::DeviceWatch(double stale_after_s, double rate_window_s)
    : stale_after_s_(stale_after_s), rate_window_s_(rate_window_s) {
  if (!(stale_after_s > 0.0) || !(rate_window_s > 0.0)) {
    throw std::invalid_argument("device health: stale_after_s and rate_window_s must be positive");
  }
}

void DeviceWatch::Arrived(double now_s) {
  if (arrivals_.empty()) first_s_ = now_s;
  last_s_ = now_s;
  arrivals_.push_back(now_s);
  while (arrivals_.front() < now_s - rate_window_s_) arrivals_.pop_front();
}

DeviceState DeviceWatch::State(double now_s, LinkView link) const {
  if (link == LinkView::kGone) return DeviceState::kDisconnected;
  if (link == LinkView::kStale || arrivals_.empty() || now_s - last_s_ > stale_after_s_) return DeviceState::kStale;
  return DeviceState::kOk;
}

double DeviceWatch::RateHz(double now_s) const {
  const double since = std::max(now_s - rate_window_s_, first_s_);
  const auto counted = std::count_if(arrivals_.begin(), arrivals_.end(), [since](double t) { return t > since; });
  const double span = now_s - since;
  return span > 0.0 ? static_cast<double>(counted) / span : 0.0;
}

}  // namespace corridor::nav
