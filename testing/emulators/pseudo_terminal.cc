#include "testing/emulators/pseudo_terminal.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <thread>

namespace corridor::testing {

PseudoTerminal::PseudoTerminal(std::filesystem::path link) : link_(std::move(link)) { Plug(); }

PseudoTerminal::~PseudoTerminal() { Unplug(); }

void PseudoTerminal::Plug() {
  Unplug();
  if (::openpty(&master_, &slave_, nullptr, nullptr, nullptr) != 0) {
    master_ = slave_ = -1;
    throw std::system_error(errno, std::generic_category(), "openpty");
  }
  // Raw: no echo of the driver's bytes, no line discipline.
  termios raw{};
  ::tcgetattr(slave_, &raw);
  ::cfmakeraw(&raw);
  ::tcsetattr(slave_, TCSANOW, &raw);
  ::fcntl(master_, F_SETFL, ::fcntl(master_, F_GETFL) | O_NONBLOCK);
  const std::string name = ::ttyname(slave_);
  std::filesystem::remove(link_);
  std::filesystem::create_symlink(name, link_);
}

void PseudoTerminal::Unplug() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
  master_ = slave_ = -1;
  std::error_code ignored;
  std::filesystem::remove(link_, ignored);
}

void PseudoTerminal::Receive(std::vector<std::uint8_t>& into, int timeout_ms) {
  if (master_ < 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));  // an unplugged device's time passing
    return;
  }
  pollfd p{master_, POLLIN, 0};
  ::poll(&p, 1, timeout_ms);
  std::uint8_t buffer[256];
  for (ssize_t n; (n = ::read(master_, buffer, sizeof buffer)) > 0;) into.insert(into.end(), buffer, buffer + n);
}

void PseudoTerminal::Send(std::span<const std::uint8_t> bytes) {
  std::size_t at = 0;
  while (master_ >= 0 && at < bytes.size()) {
    const ssize_t n = ::write(master_, bytes.data() + at, bytes.size() - at);
    if (n <= 0) {
      if (errno != EAGAIN) return;
      pollfd p{master_, POLLOUT, 0};
      if (::poll(&p, 1, 5) <= 0) return;  // nobody reads: the bytes are lost, as on a real line
      continue;
    }
    at += static_cast<std::size_t>(n);
  }
}

}  // namespace corridor::testing
