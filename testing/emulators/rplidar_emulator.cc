#include "testing/emulators/rplidar_emulator.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

namespace corridor::testing {
namespace {

double NowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The protocol's response descriptor: A5 5A, the response's length in the low 30 bits and the send mode in the top
// two of a little-endian word, the data type.
std::vector<std::uint8_t> Descriptor(std::uint32_t length, bool repeated, std::uint8_t type) {
  const std::uint32_t word = length | (repeated ? 0x40000000u : 0u);
  return {0xA5, 0x5A, static_cast<std::uint8_t>(word & 0xFF), static_cast<std::uint8_t>((word >> 8) & 0xFF),
          static_cast<std::uint8_t>((word >> 16) & 0xFF), static_cast<std::uint8_t>(word >> 24), type};
}

}  // namespace

RplidarEmulator::RplidarEmulator(std::filesystem::path link, RplidarEmulatorOptions options)
    : link_(std::move(link)), options_(std::move(options)), health_status_(options_.health_status) {
  Open();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

RplidarEmulator::~RplidarEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
  Close();
}

void RplidarEmulator::Open() {
  int master = -1;
  int slave = -1;
  if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) {
    throw std::system_error(errno, std::generic_category(), "openpty");
  }
  termios raw{};
  ::tcgetattr(slave, &raw);
  ::cfmakeraw(&raw);
  ::tcsetattr(slave, TCSANOW, &raw);
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
  const std::string name = ::ttyname(slave);
  std::filesystem::remove(link_);
  std::filesystem::create_symlink(name, link_);
  master_ = master;
  slave_ = slave;
  scanning_ = false;
  request_.clear();
}

void RplidarEmulator::Close() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
  master_ = slave_ = -1;
  std::error_code ignored;
  std::filesystem::remove(link_, ignored);
}

void RplidarEmulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void RplidarEmulator::BadCheckBit() {
  std::lock_guard lock(mutex_);
  bad_check_ = true;
}
void RplidarEmulator::DropByte() {
  std::lock_guard lock(mutex_);
  drop_byte_ = true;
}
void RplidarEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void RplidarEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void RplidarEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  Close();
}
void RplidarEmulator::Replug() {
  std::lock_guard lock(mutex_);
  Close();
  Open();
  health_status_ = options_.health_status;
}

void RplidarEmulator::Send(const std::vector<std::uint8_t>& bytes) {
  std::size_t at = 0;
  while (master_ >= 0 && at < bytes.size()) {
    const ssize_t n = ::write(master_, bytes.data() + at, bytes.size() - at);
    if (n <= 0) {
      if (errno != EAGAIN) return;  // nobody at the other end
      pollfd p{master_, POLLOUT, 0};
      ::poll(&p, 1, 5);
      continue;
    }
    at += static_cast<std::size_t>(n);
  }
}

void RplidarEmulator::SendNode(int index) {
  const double angle = 360.0 * index / options_.samples;  // clockwise from forward
  const double range = options_.range(angle);
  const int quality = range > 0.0 ? 47 : 0;
  const auto angle_q6 = static_cast<std::uint16_t>(std::lround(angle * 64.0));
  const auto distance_q2 = static_cast<std::uint16_t>(std::lround(std::max(0.0, range) * 4000.0));
  const bool start = index == 0;
  std::vector<std::uint8_t> node = {
      static_cast<std::uint8_t>(quality << 2 | (start ? 0x1 : 0x2)),
      static_cast<std::uint8_t>((angle_q6 & 0x7F) << 1 | 0x1),
      static_cast<std::uint8_t>(angle_q6 >> 7),
      static_cast<std::uint8_t>(distance_q2 & 0xFF),
      static_cast<std::uint8_t>(distance_q2 >> 8),
  };
  if (!noise_.empty()) {
    Send(noise_);
    noise_.clear();
  }
  if (bad_check_) {
    node[1] &= 0xFE;
    bad_check_ = false;
  }
  if (drop_byte_) {
    node.erase(node.begin() + 2);
    drop_byte_ = false;
  }
  Send(node);
}

void RplidarEmulator::Handle(std::uint8_t command) {
  switch (command) {
    case 0x25:  // STOP
      scanning_ = false;
      break;
    case 0x40:  // RESET: reboots, printing its banner as text, and is healthy again
      scanning_ = false;
      health_status_ = 0;
      ++resets_;
      Send(std::vector<std::uint8_t>{'R', 'P', ' ', 'L', 'I', 'D', 'A', 'R', ' ', 'S', 'y', 's', 't', 'e', 'm', '.',
                                     '\r', '\n'});
      break;
    case 0x20:  // SCAN
    case 0x21:  // FORCE_SCAN
      if (health_status_ == 2) break;  // in protection stop: no scan until reset
      Send(Descriptor(5, true, 0x81));
      scanning_ = true;
      next_sample_ = 0;
      sent_until_s_ = NowS();
      ++scans_started_;
      break;
    case 0x50: {  // GET_INFO: model, firmware minor and major, hardware, 16-byte serial
      std::vector<std::uint8_t> info = Descriptor(20, false, 0x04);
      const std::vector<std::uint8_t> body = {0x18, 29, 1, 7, 0xC0, 0xFF, 0xEE, 0x00, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
      info.insert(info.end(), body.begin(), body.end());
      Send(info);
      break;
    }
    case 0x52: {  // GET_HEALTH: status and a 16-bit error code
      std::vector<std::uint8_t> health = Descriptor(3, false, 0x06);
      health.push_back(static_cast<std::uint8_t>(health_status_));
      health.push_back(health_status_ == 2 ? 0x01 : 0x00);
      health.push_back(0x00);
      Send(health);
      break;
    }
    default:
      break;  // not emulated: a real device ignores what it does not know
  }
}

void RplidarEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    int master = -1;
    {
      std::lock_guard lock(mutex_);
      master = master_;
    }
    pollfd p{master, POLLIN, 0};
    ::poll(master >= 0 ? &p : nullptr, master >= 0 ? 1 : 0, 2);
    std::lock_guard lock(mutex_);
    if (master_ < 0 || master_ != master) continue;
    std::uint8_t buffer[64];
    for (ssize_t n; (n = ::read(master_, buffer, sizeof buffer)) > 0;) {
      if (!silent_) request_.insert(request_.end(), buffer, buffer + n);  // silent: deaf too
    }
    // Requests: A5 and the command; commands from 0x80 up carry a size, a payload and a checksum.
    while (!request_.empty()) {
      if (request_[0] != 0xA5) {
        request_.erase(request_.begin());
        continue;
      }
      if (request_.size() < 2) break;
      const std::uint8_t command = request_[1];
      std::size_t length = 2;
      if (command >= 0x80) {
        if (request_.size() < 3) break;
        length = 3 + request_[2] + 1;
      }
      if (request_.size() < length) break;
      request_.erase(request_.begin(), request_.begin() + static_cast<std::ptrdiff_t>(length));
      Handle(command);
    }
    if (!scanning_ || silent_) {
      sent_until_s_ = NowS();
      continue;
    }
    // The samples due by now, at the device's rate.
    const double period_s = 1.0 / (options_.revolutions_hz * options_.samples);
    for (int sent = 0; sent_until_s_ + period_s <= NowS() && sent < 1000; ++sent) {
      SendNode(next_sample_);
      next_sample_ = (next_sample_ + 1) % options_.samples;
      sent_until_s_ += period_s;
    }
  }
}

}  // namespace corridor::testing
