// The health of one of the robot's devices as the daemon reports it (GET /api/v1/devices, the stream, the console):
// ok while its data arrive within stale_after_s of each other; stale when they stop (the command gate stops forward
// motion, or the robot, at the same timeouts); disconnected when its driver has lost the device (a native driver
// watches its link byte by byte: a port that failed or a device silent long enough to be restarted). The data rate is
// counted over the last rate_window_s. Pure logic: the caller reports arrivals and asks, on one clock (seconds).
#pragma once

#include <deque>

namespace corridor::nav {

enum class DeviceState { kOk, kStale, kDisconnected };
const char* ToString(DeviceState state);

// What the device's driver says of its link: kNotWatched for drivers that do not watch one (the simulator, DDS).
enum class LinkView { kNotWatched, kUp, kStale, kGone };

class DeviceWatch {
 public:
  // Throws std::invalid_argument unless both times are positive.
  DeviceWatch(double stale_after_s, double rate_window_s = 2.0);

  // Data from the device arrived at now_s (times never go back).
  void Arrived(double now_s);

  DeviceState State(double now_s, LinkView link) const;
  // Arrivals a second over the last rate window (or since the first arrival, when that is sooner).
  double RateHz(double now_s) const;
  // Seconds since the last arrival; negative before the first.
  double AgeS(double now_s) const { return arrivals_.empty() ? -1.0 : now_s - last_s_; }

 private:
  double stale_after_s_;
  double rate_window_s_;
  double first_s_ = 0.0;
  double last_s_ = 0.0;
  std::deque<double> arrivals_;  // within the rate window of the last arrival
};

}  // namespace corridor::nav
