#include "testing/emulators/lds_emulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

void PutLittle16(std::vector<std::uint8_t>& out, long value) {
  const auto v = static_cast<std::uint16_t>(std::clamp<long>(value, 0, 0xFFFF));
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}

// LDROBOT's CRC-8 by its table: entry n is the remainder of n times x^8 divided by x^8 + x^6 + x^3 + x^2 + 1 (0x14D).
std::uint8_t LdCrc(const std::vector<std::uint8_t>& bytes) {
  static const std::vector<std::uint8_t> table = [] {
    std::vector<std::uint8_t> t(256);
    for (unsigned n = 0; n < 256; ++n) {
      unsigned r = n << 8;
      for (int bit = 15; bit >= 8; --bit) {
        if ((r & (1u << bit)) != 0) r ^= 0x14Du << (bit - 8);
      }
      t[n] = static_cast<std::uint8_t>(r);
    }
    return t;
  }();
  std::uint8_t crc = 0;
  for (const std::uint8_t b : bytes) crc = table[crc ^ b];
  return crc;
}

}  // namespace

LdsEmulator::LdsEmulator(std::filesystem::path link, LdsEmulatorOptions options)
    : options_(std::move(options)), terminal_(std::move(link)) {
  sent_until_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

LdsEmulator::~LdsEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void LdsEmulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void LdsEmulator::Corrupt() {
  std::lock_guard lock(mutex_);
  corrupt_ = true;
}
void LdsEmulator::DropByte() {
  std::lock_guard lock(mutex_);
  drop_byte_ = true;
}
void LdsEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void LdsEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void LdsEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
  started_ = false;
}
void LdsEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  started_ = false;
}
bool LdsEmulator::sending() const {
  std::lock_guard lock(mutex_);
  return terminal_.plugged() && !silent_ && (!options_.lds01 || started_);
}
int LdsEmulator::starts() const {
  std::lock_guard lock(mutex_);
  return starts_;
}

std::vector<std::uint8_t> LdsEmulator::Packet(int index) const {
  std::vector<std::uint8_t> out;
  const auto mm = [&](double angle) {
    return std::lround(std::max(0.0, options_.range(std::fmod(angle, 360.0))) * 1000.0);
  };
  if (options_.lds01) {
    // Start byte, index, speed, six readings of intensity, distance and two reserved bytes, two check bytes.
    out = {0xFA, static_cast<std::uint8_t>(0xA0 + index)};
    PutLittle16(out, std::lround(options_.revolutions_hz * 60.0 * 10.0));
    for (int i = 0; i < 6; ++i) {
      const long distance = mm(6.0 * index + i);
      PutLittle16(out, distance > 0 ? 1200 : 0);
      PutLittle16(out, distance);
      PutLittle16(out, 0);
    }
    PutLittle16(out, 0);  // not emulated: the document gives no rule for them
    return out;
  }
  // 0x54, 0x2C, speed in degrees a second, start angle, 12 points, end angle, timestamp, CRC. A packet spans 12 of the
  // revolution's 360 one-degree steps.
  const double start = 12.0 * index;
  out = {0x54, 0x2C};
  PutLittle16(out, std::lround(options_.revolutions_hz * 360.0));
  PutLittle16(out, std::lround(start * 100.0));
  for (int i = 0; i < 12; ++i) {
    const long distance = mm(start + i);
    PutLittle16(out, distance);
    out.push_back(distance > 0 ? 200 : 0);
  }
  PutLittle16(out, std::lround(std::fmod(start + 11.0, 360.0) * 100.0));
  PutLittle16(out, std::lround(std::fmod(NowS() * 1000.0, 30000.0)));
  out.push_back(LdCrc(out));
  return out;
}

void LdsEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the device's pace; the faults' lock free meanwhile
  }
}

void LdsEmulator::Step() {
  std::vector<std::uint8_t> received;
  terminal_.Receive(received, 0);
  for (const std::uint8_t c : received) {
    if (c == 'b' && !started_) {
      started_ = true;
      ++starts_;
    }
    if (c == 'e') started_ = false;
  }
  if (!terminal_.plugged() || silent_ || (options_.lds01 && !started_)) {
    sent_until_s_ = NowS();
    return;
  }
  const double period_s = 1.0 / (options_.revolutions_hz * PacketsPerRevolution());
  for (int sent = 0; sent_until_s_ + period_s <= NowS() && sent < 100; ++sent) {
    std::vector<std::uint8_t> packet = Packet(next_packet_);
    if (!noise_.empty()) {
      terminal_.Send(noise_);
      noise_.clear();
    }
    if (corrupt_) {
      packet[options_.lds01 ? 1 : 10] ^= options_.lds01 ? 0x40 : 0x01;  // LDS-01: an index beyond 0xDB
      corrupt_ = false;
    }
    if (drop_byte_) {
      packet.erase(packet.begin() + 7);
      drop_byte_ = false;
    }
    terminal_.Send(packet);
    next_packet_ = (next_packet_ + 1) % PacketsPerRevolution();
    sent_until_s_ += period_s;
  }
}

}  // namespace corridor::testing
