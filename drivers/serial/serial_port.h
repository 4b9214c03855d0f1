// A serial port for the native drivers (Boost.Asio), 8N1 without flow control, with reads that give up after a while
// (byte_stream.h): Boost.Asio's serial port has no timeouts of its own, and a driver must notice a device that stopped
// talking.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>

#include "drivers/serial/byte_stream.h"

namespace corridor::drivers {

class SerialPort final : public ByteStream {
 public:
  // Opens `path` at `baud_rate`; throws boost::system::system_error when it cannot (no such device, no permission).
  SerialPort(const std::filesystem::path& path, int baud_rate);

  // Throws when the port fails (the device unplugged).
  void Write(std::span<const std::uint8_t> bytes) override;
  // What arrives within timeout_s, at most into.size() bytes: 0 when nothing did. Throws when the port fails.
  std::size_t Read(std::span<std::uint8_t> into, double timeout_s) override;
  // What has arrived already, at most into.size() bytes, without waiting: 0 when nothing has. One system call where
  // Read makes two, for a reader that knows bytes are flowing. Throws when the port fails.
  std::size_t ReadArrived(std::span<std::uint8_t> into) override;
  // Reads until `count` bytes are in `out`, within timeout_s in all; false if they did not come.
  bool ReadExactly(std::vector<std::uint8_t>& out, std::size_t count, double timeout_s);
  // Reads and forgets what arrives until the line has been quiet for quiet_s.
  void Drain(double quiet_s);
  // Sets or clears the DTR line. A pseudo-terminal has no modem lines: false, which callers may ignore.
  bool SetDtr(bool on);
  // How long one byte takes on the line at the port's baud rate (8N1: ten bits).
  double byte_s() const { return byte_s_; }

 private:
  double byte_s_;
  boost::asio::io_context io_;
  boost::asio::serial_port port_;
};

}  // namespace corridor::drivers
