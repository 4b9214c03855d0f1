#include "testing/emulators/tcp_endpoint.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>

namespace corridor::testing {

TcpEndpoint::TcpEndpoint(int port) : port_(port) { Listen(); }

TcpEndpoint::~TcpEndpoint() { Unplug(); }

void TcpEndpoint::Listen() {
  listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listener_ < 0) throw std::runtime_error(std::string("tcp endpoint: socket: ") + std::strerror(errno));
  const int on = 1;
  ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<std::uint16_t>(port_));
  if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(listener_, 4) != 0) {
    const std::string error = std::strerror(errno);
    ::close(listener_);
    listener_ = -1;
    throw std::runtime_error("tcp endpoint: listening on port " + std::to_string(port_) + ": " + error);
  }
  socklen_t length = sizeof address;
  ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
}

void TcpEndpoint::Unplug() {
  if (client_ >= 0) ::close(client_);
  if (listener_ >= 0) ::close(listener_);
  client_ = listener_ = -1;
}

void TcpEndpoint::Plug() {
  if (listener_ < 0) Listen();
}

void TcpEndpoint::Accept() {
  if (listener_ < 0) return;
  const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
  if (fd < 0) return;
  if (client_ >= 0) ::close(client_);
  client_ = fd;
  const int on = 1;
  ::setsockopt(client_, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
}

void TcpEndpoint::Receive(std::vector<std::uint8_t>& into, int timeout_ms) {
  Accept();
  if (client_ < 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
    return;
  }
  pollfd p{client_, POLLIN, 0};
  ::poll(&p, 1, timeout_ms);
  std::uint8_t buffer[256];
  for (;;) {
    const ssize_t n = ::read(client_, buffer, sizeof buffer);
    if (n > 0) {
      into.insert(into.end(), buffer, buffer + n);
      continue;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {  // the host went away
      ::close(client_);
      client_ = -1;
    }
    return;
  }
}

void TcpEndpoint::Send(std::span<const std::uint8_t> bytes) {
  std::size_t at = 0;
  while (client_ >= 0 && at < bytes.size()) {
    const ssize_t n = ::send(client_, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
    if (n <= 0) {
      if (errno != EAGAIN) return;
      pollfd p{client_, POLLOUT, 0};
      if (::poll(&p, 1, 5) <= 0) return;  // nobody reads: the bytes are lost
      continue;
    }
    at += static_cast<std::size_t>(n);
  }
}

}  // namespace corridor::testing
