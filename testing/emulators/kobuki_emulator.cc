#include "testing/emulators/kobuki_emulator.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

constexpr double kPacketPeriodS = 0.02;  // feedback at 50 Hz
constexpr double kKobukiTrackM = 0.230;
constexpr double kKobukiCountsPerMetre = 2578.33 / (std::numbers::pi * 0.070);

void Little16(std::vector<std::uint8_t>& out, int value) {
  const auto word = static_cast<std::uint16_t>(value);
  out.push_back(static_cast<std::uint8_t>(word & 0xFF));
  out.push_back(static_cast<std::uint8_t>(word >> 8));
}

int Counts(double counts) { return static_cast<int>(std::fmod(std::floor(counts), 65536.0)); }

}  // namespace

KobukiEmulator::KobukiEmulator(std::filesystem::path link) : terminal_(std::move(link)) {
  start_s_ = last_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

KobukiEmulator::~KobukiEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

std::pair<double, double> KobukiEmulator::wheels_mps() const {
  std::lock_guard lock(mutex_);
  return {left_mps_, right_mps_};
}
int KobukiEmulator::base_controls() const {
  std::lock_guard lock(mutex_);
  return base_controls_;
}
void KobukiEmulator::SetCliff(bool cliff) {
  std::lock_guard lock(mutex_);
  cliff_ = cliff;
}
void KobukiEmulator::SetBump(bool bump) {
  std::lock_guard lock(mutex_);
  bump_ = bump;
}
void KobukiEmulator::SetWheelDrop(bool dropped) {
  std::lock_guard lock(mutex_);
  wheel_drop_ = dropped;
}
void KobukiEmulator::SetBattery(double volts, int charger) {
  std::lock_guard lock(mutex_);
  battery_v_ = volts;
  charger_ = charger;
}
void KobukiEmulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void KobukiEmulator::BadChecksum() {
  std::lock_guard lock(mutex_);
  bad_checksum_ = true;
}
void KobukiEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void KobukiEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void KobukiEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
}
void KobukiEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  received_.clear();
  left_mps_ = right_mps_ = 0.0;
}

void KobukiEmulator::Handle(std::uint8_t id, const std::uint8_t* data, std::size_t length) {
  if (id != 1 || length != 4) return;  // Base Control only; the rest is not emulated
  ++base_controls_;
  const double speed = static_cast<std::int16_t>(data[0] | data[1] << 8) / 1000.0;
  const int radius_mm = static_cast<std::int16_t>(data[2] | data[3] << 8);
  if (radius_mm == 0) {  // straight
    left_mps_ = right_mps_ = speed;
  } else if (radius_mm == 1) {  // on the spot, counter-clockwise for a positive speed
    left_mps_ = -speed;
    right_mps_ = speed;
  } else {
    // The outer wheel at the speed; the inner one on a circle a track nearer the centre.
    const double r = std::abs(radius_mm) / 1000.0;
    const double inner = speed * (r - kKobukiTrackM / 2.0) / (r + kKobukiTrackM / 2.0);
    left_mps_ = radius_mm > 0 ? inner : speed;
    right_mps_ = radius_mm > 0 ? speed : inner;
  }
}

std::vector<std::uint8_t> KobukiEmulator::Packet() const {
  std::vector<std::uint8_t> payload;
  // Basic Sensor Data: time stamp, bumper, wheel drop, cliff, encoders, PWM, buttons, charger, battery, over-current.
  payload.push_back(1);
  payload.push_back(15);
  Little16(payload, static_cast<int>(std::fmod((last_s_ - start_s_) * 1000.0, 65536.0)));
  payload.push_back(bump_ ? 0x02 : 0x00);
  payload.push_back(wheel_drop_ ? 0x03 : 0x00);
  payload.push_back(cliff_ ? 0x02 : 0x00);
  Little16(payload, Counts(left_counts_));
  Little16(payload, Counts(right_counts_));
  payload.push_back(0);
  payload.push_back(0);
  payload.push_back(0);
  payload.push_back(static_cast<std::uint8_t>(charger_));
  payload.push_back(static_cast<std::uint8_t>(std::lround(battery_v_ * 10.0)));
  payload.push_back(0);
  // Inertial Sensor: the heading in hundredths of a degree, its rate, and three bytes unused.
  payload.push_back(4);
  payload.push_back(7);
  Little16(payload, static_cast<int>(std::lround(std::remainder(heading_rad_, 2.0 * std::numbers::pi) * 18000.0 /
                                                 std::numbers::pi)));
  Little16(payload, 0);
  payload.insert(payload.end(), {0, 0, 0});
  // Current: one byte a motor, in 10 mA (not read by corridor's driver: passed over by its length).
  payload.insert(payload.end(), {6, 2, 12, 12});
  std::vector<std::uint8_t> packet{0xAA, 0x55, static_cast<std::uint8_t>(payload.size())};
  std::uint8_t checksum = packet[2];
  for (const std::uint8_t b : payload) {
    packet.push_back(b);
    checksum ^= b;
  }
  packet.push_back(static_cast<std::uint8_t>(checksum ^ (bad_checksum_ ? 0x5A : 0x00)));
  return packet;
}

void KobukiEmulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  terminal_.Receive(bytes, 0);
  if (!silent_) received_.insert(received_.end(), bytes.begin(), bytes.end());
  // Whole packets; what does not begin one is skipped, a packet whose checksum fails is dropped.
  while (received_.size() >= 4) {
    if (received_[0] != 0xAA || received_[1] != 0x55) {
      received_.erase(received_.begin());
      continue;
    }
    const std::size_t length = received_[2];
    if (received_.size() < 4 + length) break;
    std::uint8_t checksum = received_[2];
    for (std::size_t i = 0; i < length; ++i) checksum ^= received_[3 + i];
    if (checksum == received_[3 + length]) {
      for (std::size_t at = 3; at + 2 <= 3 + length;) {
        const std::size_t size = received_[at + 1];
        if (at + 2 + size > 3 + length) break;
        Handle(received_[at], received_.data() + at + 2, size);
        at += 2 + size;
      }
      received_.erase(received_.begin(), received_.begin() + static_cast<std::ptrdiff_t>(4 + length));
    } else {
      received_.erase(received_.begin());
    }
  }
  const double dt = now_s - last_s_;
  last_s_ = now_s;
  left_counts_ = std::fmod(left_counts_ + left_mps_ * dt * kKobukiCountsPerMetre + 65536.0, 65536.0);
  right_counts_ = std::fmod(right_counts_ + right_mps_ * dt * kKobukiCountsPerMetre + 65536.0, 65536.0);
  heading_rad_ += (right_mps_ - left_mps_) / kKobukiTrackM * dt;
  if (silent_ || now_s < next_packet_s_) return;
  next_packet_s_ = now_s + kPacketPeriodS;
  if (!noise_.empty()) {
    terminal_.Send(noise_);
    noise_.clear();
  }
  terminal_.Send(Packet());
  bad_checksum_ = false;
}

void KobukiEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the robot's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
