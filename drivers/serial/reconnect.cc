#include "drivers/serial/reconnect.h"

#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>

#include <spdlog/spdlog.h>

#include "drivers/serial/link_state.h"

namespace corridor::drivers {

bool LinkStatus::Set(std::string_view device, std::string_view port, LinkState to, std::string error) {
  const bool changed = to != state;
  if (changed || (!error.empty() && error != last_error)) {
    if (error.empty()) {
      spdlog::info("{} {}: {}", device, port, ToString(to));
    } else {
      spdlog::warn("{} {}: {}: {}", device, port, ToString(to), error);
    }
  }
  state = to;
  if (!error.empty()) last_error = std::move(error);
  return changed;
}

void RunReconnecting(std::stop_token stop, const std::string& device, double reconnect_s,
                     const std::function<void()>& session, const std::function<void(const std::string&)>& failed,
                     const std::function<void()>& retrying) {
  pthread_setname_np(pthread_self(), ("dev-" + device).substr(0, 15).c_str());
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
