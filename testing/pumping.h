// A stand-in for the daemon's control loop in the drivers' tests: a thread that pumps a native driver
// (DeviceLink::Pump) every control tick until it is destroyed, and says which thread it is. Given several ticks, it
// waits each in turn, over and over: a control loop that is late now and then.
#pragma once

#include <chrono>
#include <cstddef>
#include <thread>
#include <vector>

#include "drivers/serial/link_state.h"

namespace corridor::testing {

class Pumping {
 public:
  explicit Pumping(drivers::DeviceLink& link, std::chrono::milliseconds tick = std::chrono::milliseconds(20))
      : Pumping(link, std::vector{tick}) {}
  Pumping(drivers::DeviceLink& link, std::vector<std::chrono::milliseconds> ticks)
      : thread_([&link, ticks = std::move(ticks)](std::stop_token stop) {
          for (std::size_t i = 0; !stop.stop_requested(); i = (i + 1) % ticks.size()) {
            link.Pump();
            std::this_thread::sleep_for(ticks[i]);
          }
        }) {}

  std::thread::id id() const { return thread_.get_id(); }

 private:
  std::jthread thread_;
};

}  // namespace corridor::testing
