// Time sources. Everything that needs "now" takes a Clock so the same code runs in real time on the robot
// and in simulated time (faster than real time, in lockstep) in tools and tests.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

namespace corridor::drivers {

// Nanoseconds since an arbitrary epoch that is fixed for the life of the clock.
using TimeNs = std::int64_t;
inline constexpr TimeNs kNsPerSecond = 1'000'000'000;
inline double ToSeconds(TimeNs ns) { return static_cast<double>(ns) * 1e-9; }
inline TimeNs FromSeconds(double s) { return static_cast<TimeNs>(s * 1e9); }

// Thread-safe: Now() may be called from any thread.
class Clock {
 public:
  Clock() = default;
  Clock(const Clock&) = delete;
  Clock& operator=(const Clock&) = delete;
  virtual ~Clock() = default;
  virtual TimeNs Now() const = 0;
};

// Monotonic wall time.
class SteadyClock final : public Clock {
 public:
  TimeNs Now() const override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

// Time that only moves when its owner advances it (the simulator).
class ManualClock final : public Clock {
 public:
  TimeNs Now() const override { return now_.load(std::memory_order_acquire); }
  void Set(TimeNs t) { now_.store(t, std::memory_order_release); }

 private:
  std::atomic<TimeNs> now_{0};
};

}  // namespace corridor::drivers
