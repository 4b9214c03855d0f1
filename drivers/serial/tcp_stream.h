// A TCP connection to a device on Ethernet (a Hokuyo UST's SCIP port), through Boost.Asio, with a connect and reads
// that give up after a while.
#pragma once

#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "drivers/serial/byte_stream.h"

namespace corridor::drivers {

class TcpStream final : public ByteStream {
 public:
  // Connects to host:port (an address or a name) within connect_s; throws boost::system::system_error when it cannot
  // (refused, no route, timed out).
  TcpStream(const std::string& host, int port, double connect_s);

  void Write(std::span<const std::uint8_t> bytes) override;
  std::size_t Read(std::span<std::uint8_t> into, double timeout_s) override;
  std::size_t ReadArrived(std::span<std::uint8_t> into) override;

 private:
  boost::asio::io_context io_;
  boost::asio::ip::tcp::socket socket_;
};

}  // namespace corridor::drivers
