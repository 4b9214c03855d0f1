#include "testing/emulators/rplidar_emulator.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

// The protocol's response descriptor: A5 5A, the response's length in the low 30 bits and the send mode in the top
// two of a little-endian word, the data type.
std::vector<std::uint8_t> Descriptor(std::uint32_t length, bool repeated, std::uint8_t type) {
  const std::uint32_t word = length | (repeated ? 0x40000000u : 0u);
  return {0xA5,
          0x5A,
          static_cast<std::uint8_t>(word & 0xFF),
          static_cast<std::uint8_t>((word >> 8) & 0xFF),
          static_cast<std::uint8_t>((word >> 16) & 0xFF),
          static_cast<std::uint8_t>(word >> 24),
          type};
}

}  // namespace

RplidarEmulator::RplidarEmulator(std::filesystem::path link, RplidarEmulatorOptions options)
    : options_(std::move(options)), terminal_(std::move(link)), health_status_(options_.health_status) {
  if (options_.pace == Pace::kOwnThread) thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

void RplidarEmulator::Tick(double now_s) {
  std::lock_guard lock(mutex_);
  Step(now_s);
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

void RplidarEmulator::SendWithFaults(std::vector<std::uint8_t> bytes, std::size_t check_byte, std::uint8_t check_mask) {
  if (!noise_.empty()) {
    Send(noise_);
    noise_.clear();
  }
  if (bad_check_) {
    bytes[check_byte] ^= check_mask;
    bad_check_ = false;
  }
  if (drop_byte_) {
    bytes.erase(bytes.begin() + 2);
    drop_byte_ = false;
  }
  Send(bytes);
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
  SendWithFaults(std::move(node), 1, 0x01);  // the check bit cleared
}

void RplidarEmulator::SendCapsule(int first_index) {
  // The document's capsule: sync 0xA and 0x5 in the top nibbles of bytes 0 and 1 over the checksum's low and high
  // nibbles; the start angle ω in 1/64 degree with S in bit 15; 16 cabins of two samples. Sample k is measured at
  // ω + k/32 of the way to the next capsule's ω, less its correction dθ (6-bit two's complement, 1/8 degree): this
  // device's corrections run -0.75..+0.75 degrees, so that a decoder that drops them or their sign is off.
  const auto place = [&](int index) { return 360.0 * (index % options_.samples) / options_.samples; };
  const auto angle_q6 = static_cast<std::uint16_t>(std::lround(place(first_index) * 64.0) % (360 * 64));
  std::vector<std::uint8_t> capsule(84, 0);
  const std::uint16_t angle_word = angle_q6 | (first_capsule_ ? 0x8000 : 0x0000);
  first_capsule_ = false;
  capsule[2] = static_cast<std::uint8_t>(angle_word & 0xFF);
  capsule[3] = static_cast<std::uint8_t>(angle_word >> 8);
  for (int k = 0; k < 32; ++k) {
    const int correction_eighths = (k % 7) - 3;  // -3..3 eighths of a degree
    const double angle = place(first_index) + (360.0 / options_.samples) * k - correction_eighths / 8.0;
    const double range = options_.range(std::fmod(angle + 360.0, 360.0));
    const auto mm = static_cast<std::uint16_t>(std::min(0x3FFFL, std::lround(std::max(0.0, range) * 1000.0)));
    const auto correction = static_cast<std::uint8_t>(correction_eighths & 0x3F);
    const std::size_t at = 4 + static_cast<std::size_t>(k / 2) * 5;
    const std::size_t word = at + static_cast<std::size_t>(k % 2) * 2;
    capsule[word] = static_cast<std::uint8_t>(((mm & 0x3F) << 2) | (correction >> 4));
    capsule[word + 1] = static_cast<std::uint8_t>(mm >> 6);
    capsule[at + 4] |= static_cast<std::uint8_t>((correction & 0x0F) << ((k % 2) * 4));
  }
  std::uint8_t checksum = 0;
  for (std::size_t i = 2; i < capsule.size(); ++i) checksum ^= capsule[i];
  capsule[0] = static_cast<std::uint8_t>(0xA0 | (checksum & 0x0F));
  capsule[1] = static_cast<std::uint8_t>(0x50 | (checksum >> 4));
  SendWithFaults(std::move(capsule), 0, 0x01);  // the checksum's lowest bit flipped
}

void RplidarEmulator::StartScan(bool express, double now_s) {
  if (health_status_ == 2) return;  // in protection stop: no scan until reset
  Send(express ? Descriptor(84, true, 0x82) : Descriptor(5, true, 0x81));
  scanning_ = true;
  express_ = express;
  first_capsule_ = express;
  next_sample_ = 0;
  sent_until_s_ = now_s;
  ++(express ? express_scans_started_ : scans_started_);
}

void RplidarEmulator::Handle(std::uint8_t command, double now_s) {
  switch (command) {
    case 0x25:  // STOP
      scanning_ = false;
      break;
    case 0x82:  // EXPRESS_SCAN (its payload, the working mode, is taken as 0: the legacy capsules)
      StartScan(true, now_s);
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
      StartScan(false, now_s);
      break;
    case 0x50: {  // GET_INFO: model, firmware minor and major, hardware, 16-byte serial
      std::vector<std::uint8_t> info = Descriptor(20, false, 0x04);
      const std::vector<std::uint8_t> body = {0x18, 29, 1, 7, 0xC0, 0xFF, 0xEE, 0x00, 1,  2,
                                              3,    4,  5, 6, 7,    8,    9,    10,   11, 12};
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
    default: break;  // not emulated: a real device ignores what it does not know
  }
}

void RplidarEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the device's pace; the faults' lock free meanwhile
  }
}

void RplidarEmulator::Step(double now_s) {
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
    Handle(command, now_s);
  }
  if (!scanning_ || silent_) {
    sent_until_s_ = now_s;
    return;
  }
  // The samples due by now, at the device's rate: one by one, or 32 at a time in a capsule.
  const int batch = express_ ? 32 : 1;
  const double period_s = batch / (options_.revolutions_hz * options_.samples);
  for (int sent = 0; sent_until_s_ + period_s <= now_s && sent < 1000; ++sent) {
    if (express_) {
      SendCapsule(next_sample_);
    } else {
      SendNode(next_sample_);
    }
    next_sample_ = (next_sample_ + batch) % options_.samples;
    sent_until_s_ += period_s;
  }
}

}  // namespace corridor::testing
