// The device end of an emulated Ethernet device: a TCP port on 127.0.0.1 that takes one host at a time (a new
// connection replaces the one before, as a device whose host reconnected). Unplugged, the connection is closed and
// the port refuses new ones; plugged back in, it listens on the same port.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "testing/emulators/device_end.h"

namespace corridor::testing {

class TcpEndpoint final : public DeviceEnd {
 public:
  // Listens on 127.0.0.1:`port` (0: a free one). Throws std::runtime_error when it cannot.
  explicit TcpEndpoint(int port = 0);
  ~TcpEndpoint() override;

  int port() const { return port_; }
  bool connected() const { return client_ >= 0; }
  bool plugged() const override { return listener_ >= 0; }
  void Unplug() override;
  void Plug() override;
  void Receive(std::vector<std::uint8_t>& into, int timeout_ms) override;
  void Send(std::span<const std::uint8_t> bytes) override;

 private:
  void Listen();
  void Accept();  // a waiting host, if any, becomes the client

  int port_ = 0;
  int listener_ = -1;
  int client_ = -1;
};

}  // namespace corridor::testing
