#include "drivers/serial/reconnect.h"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>

namespace corridor::drivers {

void RunReconnecting(std::stop_token stop, double reconnect_s, const std::function<void()>& session,
                     const std::function<void(const std::string&)>& failed, const std::function<void()>& retrying) {
  std::mutex mutex;
  std::condition_variable_any wake;
  for (bool first = true; !stop.stop_requested(); first = false) {
    if (!first) retrying();
    try {
      session();
    } catch (const std::exception& e) {
      failed(e.what());
    }
    std::unique_lock lock(mutex);
    wake.wait_for(lock, stop, std::chrono::duration<double>(reconnect_s), [] { return false; });
  }
}

}  // namespace corridor::drivers
