#include "server/app/service.h"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

namespace corridor::server {

ServiceNotifier::ServiceNotifier(Executor& control) : control_(control) {
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    thread_ = std::thread([this, usec] { Watch(std::chrono::microseconds(usec)); });
  }
}

ServiceNotifier::~ServiceNotifier() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ServiceNotifier::Ready(const std::string& status) { sd_notifyf(0, "READY=1\nSTATUS=%s", status.c_str()); }

void ServiceNotifier::Stopping() { sd_notify(0, "STOPPING=1\nSTATUS=stopping the robot"); }

void ServiceNotifier::Watch(std::chrono::microseconds interval) {
  spdlog::info("systemd watchdog: pinging every {} ms while the control loop runs", interval.count() / 2000);
  std::unique_lock lock(mutex_);
  bool reported = false;
  while (!wake_.wait_for(lock, interval / 2, [this] { return stop_; })) {
    // A ping says the heartbeat posted last time has run: the control executor is not stuck.
    if (!heartbeat_.exchange(false)) {
      if (!reported) spdlog::error("the control loop has not run for {} ms: no watchdog ping", interval.count() / 2000);
      reported = true;
      continue;
    }
    reported = false;
    sd_notify(0, "WATCHDOG=1");
    control_.Post([this] { heartbeat_ = true; });
  }
}

}  // namespace corridor::server
