// How a native driver's link to its device stands, for its status and the device health the daemon reports.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace corridor::drivers {

enum class LinkState {
  kConnecting,    // the port is open, the device being set up
  kRunning,       // data flows
  kSilent,        // the port is open but the device said nothing for a while: restarting it
  kDisconnected,  // the port failed or is gone (unplugged): reopening it
};

inline const char* ToString(LinkState state) {
  switch (state) {
    case LinkState::kConnecting: return "connecting";
    case LinkState::kRunning: return "running";
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
  // Sets the state, and the error when one is given; a change is logged as `device` on `port`.
  void Set(std::string_view device, std::string_view port, LinkState to, std::string error = {});
};

}  // namespace corridor::drivers
