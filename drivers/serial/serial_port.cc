#include "drivers/serial/serial_port.h"

#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <array>
#include <chrono>

#include <boost/asio/write.hpp>

namespace corridor::drivers {

SerialPort::SerialPort(const std::filesystem::path& path, int baud_rate) : byte_s_(10.0 / baud_rate), port_(io_) {
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
  // poll and read on the port's descriptor: Boost.Asio's reactor (an epoll registration and a timer for every read)
  // cost a native driver's thread several times its decoding, at hundreds of reads a second.
  const int fd = port_.native_handle();
  const auto ns = static_cast<std::int64_t>(std::max(0.0, timeout_s) * 1e9);
  const timespec timeout{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  pollfd p{fd, POLLIN, 0};
  const int ready = ::ppoll(&p, 1, &timeout, nullptr);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    throw boost::system::system_error(errno, boost::system::system_category(), "waiting on the serial port");
  }
  if (ready == 0) return 0;
  return ReadArrived(into);
}

std::size_t SerialPort::ReadArrived(std::span<std::uint8_t> into) {
  // The descriptor is non-blocking (Boost.Asio opens it so): nothing there is EAGAIN.
  const ssize_t n = ::read(port_.native_handle(), into.data(), into.size());
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  if (n == 0) throw boost::system::system_error(boost::asio::error::eof, "reading the serial port");
  throw boost::system::system_error(errno, boost::system::system_category(), "reading the serial port");
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
