// The daemon's own CPU and memory, for the console's plots (the state's "process"): the CPU time of all its threads
// over the last window of at least kWindowS, as a share of one core, and its resident memory now, read from
// /proc/self (Linux's proc(5): stat's utime and stime in clock ticks, statm's resident pages). Thread-safe; reads
// /proc at most once a window however often it is asked.
#pragma once

#include <mutex>
#include <optional>

#include "drivers/clock.h"

namespace corridor::server {

struct ProcessUsageSample {
  double cpu_percent = 0.0;  // of one core, over the last window
  double resident_mb = 0.0;
};

class ProcessUsage {
 public:
  static constexpr double kWindowS = 1.0;

  // The usage as of the last window ended before `now_ns` (the real clock: CPU time is real time's); nullopt until
  // a first window has passed, or where /proc cannot be read.
  std::optional<ProcessUsageSample> Sample(drivers::TimeNs now_ns);

 private:
  std::mutex mutex_;
  drivers::TimeNs window_start_ns_ = -1;
  double window_start_cpu_s_ = 0.0;
  std::optional<ProcessUsageSample> last_;
};

}  // namespace corridor::server
