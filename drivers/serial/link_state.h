// How a native driver's link to its device stands, for its status and the device health the daemon reports.
#pragma once

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

}  // namespace corridor::drivers
