// The device end of an emulated serial device: a pseudo-terminal in raw mode whose slave a symbolic link names (as
// udev's stable names do), so that the device can be unplugged (the terminal closed, the link removed) and plugged back
// in under the same name. Not thread-safe: its emulator serialises access.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "testing/emulators/device_end.h"

namespace corridor::testing {

class PseudoTerminal final : public DeviceEnd {
 public:
  // Opens one, and points `link` at its slave.
  explicit PseudoTerminal(std::filesystem::path link);
  ~PseudoTerminal() override;

  bool plugged() const override { return master_ >= 0; }
  // Closes it and removes the link: a driver's reads fail. Plug: a new one under the same link.
  void Unplug() override;
  void Plug() override;
  // Waits up to timeout_ms for the driver's bytes and appends what came; unplugged, just waits.
  void Receive(std::vector<std::uint8_t>& into, int timeout_ms) override;
  // Sends to the driver (dropped when unplugged, or when nobody has the port open and its buffer is full).
  void Send(std::span<const std::uint8_t> bytes) override;

 private:
  std::filesystem::path link_;
  int master_ = -1;
  int slave_ = -1;
};

}  // namespace corridor::testing
