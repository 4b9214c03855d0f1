// For tests of nodes that answer on their own threads: wait until a condition holds.
#pragma once

#include <chrono>
#include <functional>
#include <thread>

namespace corridor::testing {

// True once `done` holds, polled every 10 ms; false after `timeout`.
inline bool Eventually(const std::function<bool()>& done,
                       std::chrono::milliseconds timeout = std::chrono::milliseconds(2000)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

}  // namespace corridor::testing
