// How a native driver's link to its device stands, for its status and the device health the daemon reports.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace corridor::drivers {

enum class LinkState {
  kConnecting,    // the port is open, the device being set up
  kRunning,       // data flows
  kStale,         // nothing came for stale_s: the robot must not rely on the device (it stops)
  kSilent,        // the port is open but the device said nothing for a while: restarting it
  kDisconnected,  // the port failed or is gone (unplugged): reopening it
};

inline const char* ToString(LinkState state) {
  switch (state) {
    case LinkState::kConnecting: return "connecting";
    case LinkState::kRunning: return "running";
    case LinkState::kStale: return "stale";
    case LinkState::kSilent: return "silent";
    case LinkState::kDisconnected: return "disconnected";
  }
  return "unknown";
}

// What every driver's status holds about its link (a driver's own status extends it).
struct LinkStatus {
  LinkState state = LinkState::kConnecting;
  std::uint64_t reconnects = 0;  // times the port was opened again after a failure or silence
  std::string last_error;        // empty: none yet
  // Sets the state, and the error when one is given; a change is logged as `device` on `port`. True when the state
  // changed.
  bool Set(std::string_view device, std::string_view port, LinkState to, std::string error = {});
};

// A native driver's link to its device, watched byte by byte: the daemon's device health reads it, and the command
// gate stops the robot while it is not running.
class DeviceLink {
 public:
  using LinkHandler = std::function<void(const LinkStatus&)>;

  DeviceLink() = default;
  DeviceLink(const DeviceLink&) = delete;
  DeviceLink& operator=(const DeviceLink&) = delete;
  virtual ~DeviceLink() = default;

  virtual LinkStatus link() const = 0;
  // Called on the driver's thread (or the pumping one: Pump) whenever the link's state changes; must return quickly.
  virtual void SetLinkHandler(LinkHandler handler) = 0;
  // Reads what the device sent since the last call, hands it on and writes what is due, without waiting: the
  // daemon's control loop calls it on every decision (ros2_control's read and write around its update), so that a
  // device's data costs no wake-up of a thread of its own. A device read by its own thread (a camera) ignores it.
  virtual void Pump() {}
};

// A driver's link going to `state`: `status` (a LinkStatus or a driver's status extending it) set under `mutex`, which
// also guards `handler`, and the handler called outside it when the state changed.
template <typename Status>
void ChangeLink(std::mutex& mutex, Status& status, const DeviceLink::LinkHandler& handler, std::string_view device,
                std::string_view port, LinkState state, std::string error = {}) {
  DeviceLink::LinkHandler call;
  LinkStatus now;
  {
    std::lock_guard lock(mutex);
    if (!status.Set(device, port, state, std::move(error))) return;
    call = handler;
    now = status;
  }
  if (call) call(now);
}

}  // namespace corridor::drivers
