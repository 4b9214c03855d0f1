#include "drivers/serial/tcp_stream.h"

#include <algorithm>
#include <chrono>

#include <boost/asio/connect.hpp>
#include <boost/asio/write.hpp>
#include <boost/system/system_error.hpp>

namespace corridor::drivers {
namespace {

std::chrono::microseconds Micros(double s) {
  return std::chrono::microseconds(static_cast<std::int64_t>(std::max(0.0, s) * 1e6));
}

}  // namespace

TcpStream::TcpStream(const std::string& host, int port, double connect_s) : socket_(io_) {
  boost::asio::ip::tcp::resolver resolver(io_);
  const auto endpoints = resolver.resolve(host, std::to_string(port));
  boost::system::error_code error = boost::asio::error::would_block;
  boost::asio::async_connect(socket_, endpoints, [&](const boost::system::error_code& e, const auto&) { error = e; });
  io_.run_for(Micros(connect_s));
  if (error == boost::asio::error::would_block) {
    socket_.close();
    io_.restart();
    io_.run();
    throw boost::system::system_error(boost::asio::error::timed_out,
                                      "connecting to " + host + ":" + std::to_string(port));
  }
  if (error) throw boost::system::system_error(error, "connecting to " + host + ":" + std::to_string(port));
  socket_.set_option(boost::asio::ip::tcp::no_delay(true));
  socket_.non_blocking(true);  // ReadArrived's synchronous reads never wait (Read's asynchronous ones are not affected)
}

void TcpStream::Write(std::span<const std::uint8_t> bytes) {
  boost::asio::write(socket_, boost::asio::buffer(bytes.data(), bytes.size()));
}

std::size_t TcpStream::Read(std::span<std::uint8_t> into, double timeout_s) {
  boost::system::error_code error;
  std::size_t got = 0;
  bool done = false;
  socket_.async_read_some(boost::asio::buffer(into.data(), into.size()),
                          [&](const boost::system::error_code& e, std::size_t n) {
                            error = e;
                            got = n;
                            done = true;
                          });
  io_.restart();
  io_.run_for(Micros(timeout_s));
  if (!done) {
    socket_.cancel();
    io_.restart();
    io_.run();  // the cancelled read's handler (or its data, had it just arrived)
  }
  if (error == boost::asio::error::operation_aborted) return 0;
  if (error) throw boost::system::system_error(error, "reading the connection");
  return got;
}

std::size_t TcpStream::ReadArrived(std::span<std::uint8_t> into) {
  boost::system::error_code error;
  const std::size_t got = socket_.read_some(boost::asio::buffer(into.data(), into.size()), error);
  if (error == boost::asio::error::would_block || error == boost::asio::error::try_again) return 0;
  if (error) throw boost::system::system_error(error, "reading the connection");
  return got;
}

}  // namespace corridor::drivers
