// A stand-in for the daemon's control loop in the drivers' tests: a thread that pumps a native driver
// (DeviceLink::Pump) every control tick until it is destroyed, and says which thread it is.
#pragma once

#include <chrono>
#include <thread>

#include "drivers/serial/link_state.h"

namespace corridor::testing {

class Pumping {
 public:
  explicit Pumping(drivers::DeviceLink& link, std::chrono::milliseconds tick = std::chrono::milliseconds(20))
      : thread_([&link, tick](std::stop_token stop) {
          while (!stop.stop_requested()) {
            link.Pump();
            std::this_thread::sleep_for(tick);
          }
        }) {}

  std::thread::id id() const { return thread_.get_id(); }

 private:
  std::jthread thread_;
};

}  // namespace corridor::testing
