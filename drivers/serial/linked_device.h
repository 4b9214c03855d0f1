// What every native driver keeps about its link to its device: its status (a LinkStatus, or a driver's status
// extending it) and the link handler under one mutex, each change of state reported, and the driver's sessions run on
// its thread, opened anew every reconnect_s after one ends or fails (reconnect.h). A driver derives from it, keeps its
// own handlers under the same mutex, and supplies the session.
#pragma once

#include <functional>
#include <mutex>
#include <stop_token>
#include <string>
#include <utility>

#include "drivers/serial/link_state.h"
#include "drivers/serial/reconnect.h"

namespace corridor::drivers {

template <typename Status>
class LinkedDevice : public DeviceLink {
 public:
  Status status() const {
    std::lock_guard lock(mutex_);
    return status_;
  }
  LinkStatus link() const override { return status(); }
  void SetLinkHandler(LinkHandler handler) override {
    std::lock_guard lock(mutex_);
    link_handler_ = std::move(handler);
  }

 protected:
  // `device`: the driver's name (its logs, its thread's name); `where`: the port or device it talks to.
  LinkedDevice(std::string device, std::string where) : device_(std::move(device)), where_(std::move(where)) {}

  void SetState(LinkState state, std::string error = {}) {
    ChangeLink(mutex_, status_, link_handler_, device_, where_, state, std::move(error));
  }
  // Runs `session` on the calling thread until `stop`: what it throws is the link disconnected with that error, and
  // every session after the first counts as a reconnect.
  void RunSessions(std::stop_token stop, double reconnect_s, const std::function<void()>& session) {
    RunReconnecting(
        stop, device_, reconnect_s, session,
        [&](const std::string& error) { SetState(LinkState::kDisconnected, error); },
        [&] {
          std::lock_guard lock(mutex_);
          ++status_.reconnects;
        });
  }

  mutable std::mutex mutex_;  // guards status_, the link handler and the driver's own handlers
  Status status_;

 private:
  std::string device_;
  std::string where_;
  LinkHandler link_handler_;
};

}  // namespace corridor::drivers
