// The device's end of an emulated device's wire (a pseudo-terminal for a serial device, a TCP port for an Ethernet
// one): what an emulator reads its host's bytes from and sends its own to, and can be unplugged from and plugged back
// into under the same name. Not thread-safe: its emulator serialises access.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

namespace corridor::testing {

// Seconds on the steady clock: the time an emulator paces its device and schedules its faults by.
inline double NowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Who paces an emulated device: its own thread, on the steady clock (NowS), or its owner, calling the emulator's Tick
// with the seconds of its own clock (a simulator that steps the world the device measures, so that what the device
// reports and the world it reports on keep one time however late the simulator runs).
enum class Pace { kOwnThread, kOwner };

class DeviceEnd {
 public:
  DeviceEnd() = default;
  DeviceEnd(const DeviceEnd&) = delete;
  DeviceEnd& operator=(const DeviceEnd&) = delete;
  virtual ~DeviceEnd() = default;

  virtual bool plugged() const = 0;
  // The cable pulled: the host's reads fail. Plug: back under the same name.
  virtual void Unplug() = 0;
  virtual void Plug() = 0;
  // Waits up to timeout_ms for the host's bytes and appends what came; unplugged, just waits.
  virtual void Receive(std::vector<std::uint8_t>& into, int timeout_ms) = 0;
  // Sends to the host (dropped when unplugged or when nobody is there to read).
  virtual void Send(std::span<const std::uint8_t> bytes) = 0;
};

}  // namespace corridor::testing
