// The byte stream a native driver talks to its device over: a serial port (serial_port.h) or a TCP connection
// (tcp_stream.h, for devices on Ethernet), with reads that give up after a while, so that a driver notices a device
// that stopped talking.
#pragma once

#include <charconv>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace corridor::drivers {

class ByteStream {
 public:
  ByteStream() = default;
  ByteStream(const ByteStream&) = delete;
  ByteStream& operator=(const ByteStream&) = delete;
  virtual ~ByteStream() = default;

  // Throws when the link fails (the device unplugged, the connection closed).
  virtual void Write(std::span<const std::uint8_t> bytes) = 0;
  // What arrives within timeout_s, at most into.size() bytes: 0 when nothing did. Throws when the link fails.
  virtual std::size_t Read(std::span<std::uint8_t> into, double timeout_s) = 0;
  // What has arrived already, at most into.size() bytes, without waiting: 0 when nothing has. Throws when the link
  // fails.
  virtual std::size_t ReadArrived(std::span<std::uint8_t> into) = 0;
};

// `port` as the configuration gives it: "host:port" (a TCP device, connected within connect_s) or a serial device's
// path (opened at baud_rate). Throws boost::system::system_error (or std::invalid_argument for a port number that is
// not one) when it cannot.
std::unique_ptr<ByteStream> OpenStream(const std::string& port, int baud_rate, double connect_s);
// Whether `port` names a TCP device: host:port, not a path.
inline bool IsNetworkPort(const std::string& port) {
  const std::size_t colon = port.rfind(':');
  return !port.empty() && port.front() != '/' && colon != std::string::npos && colon > 0 && colon + 1 < port.size();
}
// The TCP port of a network device's host:port; none when what follows the colon is not one (1-65535).
inline std::optional<int> NetworkPortNumber(const std::string& port) {
  const std::size_t colon = port.rfind(':');
  if (!IsNetworkPort(port)) return std::nullopt;
  int number = 0;
  const char* end = port.data() + port.size();
  const auto [at, error] = std::from_chars(port.data() + colon + 1, end, number);
  if (error != std::errc{} || at != end || number <= 0 || number > 65535) return std::nullopt;
  return number;
}

}  // namespace corridor::drivers
