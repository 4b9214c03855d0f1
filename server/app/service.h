// corridord as a systemd service (Type=notify): READY=1 once the API answers, STATUS= lines, and WATCHDOG=1 pings
// for as long as the control executor keeps running its work, so that a control loop that stalls stops the pings and
// systemd restarts the daemon (WatchdogSec=). Without NOTIFY_SOCKET (run by hand, in tests) it does nothing.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "server/runtime/executor.h"

namespace corridor::server {

class ServiceNotifier {
 public:
  // Starts pinging at half the watchdog interval systemd asks for (WATCHDOG_USEC), when it asks; `control` is the
  // executor whose progress the pings stand for.
  explicit ServiceNotifier(Executor& control);
  ServiceNotifier(const ServiceNotifier&) = delete;
  ServiceNotifier& operator=(const ServiceNotifier&) = delete;
  ~ServiceNotifier();

  void Ready(const std::string& status);
  void Stopping();

 private:
  void Watch(std::chrono::microseconds interval);

  Executor& control_;
  std::atomic<bool> heartbeat_{true};  // the last heartbeat posted to the control executor has run
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace corridor::server
