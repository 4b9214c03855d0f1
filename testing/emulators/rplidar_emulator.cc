#include "testing/emulators/rplidar_emulator.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

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
    : options_(std::move(options)), terminal_(std::move(link)), health_status_(options_.health_status) {
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

RplidarEmulator::~RplidarEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
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
  terminal_.Unplug();
  scanning_ = false;
}
void RplidarEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  scanning_ = false;
  request_.clear();
  health_status_ = options_.health_status;
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
    {
      std::lock_guard lock(mutex_);
      Step();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the device's pace; the faults' lock free meanwhile
  }
}

void RplidarEmulator::Step() {
  std::vector<std::uint8_t> received;
  terminal_.Receive(received, 0);
  if (!silent_) request_.insert(request_.end(), received.begin(), received.end());  // silent: deaf too
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
    return;
  }
  // The samples due by now, at the device's rate.
  const double period_s = 1.0 / (options_.revolutions_hz * options_.samples);
  for (int sent = 0; sent_until_s_ + period_s <= NowS() && sent < 1000; ++sent) {
    SendNode(next_sample_);
    next_sample_ = (next_sample_ + 1) % options_.samples;
    sent_until_s_ += period_s;
  }
}

}  // namespace corridor::testing
