#include "drivers/serial/serial_port.h"

#include <sys/ioctl.h>

#include <algorithm>
#include <array>
#include <chrono>

#include <boost/asio/write.hpp>

namespace corridor::drivers {

SerialPort::SerialPort(const std::filesystem::path& path, int baud_rate) : port_(io_) {
  using boost::asio::serial_port_base;
  port_.open(path.string());
  port_.set_option(serial_port_base::baud_rate(static_cast<unsigned>(baud_rate)));
  port_.set_option(serial_port_base::character_size(8));
  port_.set_option(serial_port_base::parity(serial_port_base::parity::none));
  port_.set_option(serial_port_base::stop_bits(serial_port_base::stop_bits::one));
  port_.set_option(serial_port_base::flow_control(serial_port_base::flow_control::none));
}

void SerialPort::Write(std::span<const std::uint8_t> bytes) {
  boost::asio::write(port_, boost::asio::buffer(bytes.data(), bytes.size()));
}

std::size_t SerialPort::Read(std::span<std::uint8_t> into, double timeout_s) {
  boost::system::error_code error;
  std::size_t got = 0;
  bool done = false;
  port_.async_read_some(boost::asio::buffer(into.data(), into.size()),
                        [&](const boost::system::error_code& e, std::size_t n) {
                          error = e;
                          got = n;
                          done = true;
                        });
  io_.restart();
  io_.run_for(std::chrono::microseconds(static_cast<std::int64_t>(std::max(0.0, timeout_s) * 1e6)));
  if (!done) {
    port_.cancel();
    io_.restart();
    io_.run();  // the cancelled read's handler (or its data, had it just arrived)
  }
  if (error == boost::asio::error::operation_aborted) return 0;
  if (error) throw boost::system::system_error(error, "reading the serial port");
  return got;
}

bool SerialPort::ReadExactly(std::vector<std::uint8_t>& out, std::size_t count, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  std::array<std::uint8_t, 256> buffer{};
  while (out.size() < count) {
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0.0) return false;
    const std::size_t want = std::min(buffer.size(), count - out.size());
    const std::size_t n = Read(std::span<std::uint8_t>(buffer.data(), want), left);
    out.insert(out.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
  }
  return true;
}

void SerialPort::Drain(double quiet_s) {
  std::array<std::uint8_t, 256> buffer{};
  while (Read(buffer, quiet_s) > 0) {
  }
}

bool SerialPort::SetDtr(bool on) {
  int dtr = TIOCM_DTR;
  return ::ioctl(port_.native_handle(), on ? TIOCMBIS : TIOCMBIC, &dtr) == 0;
}

}  // namespace corridor::drivers
