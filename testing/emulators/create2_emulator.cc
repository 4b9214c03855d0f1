#include "testing/emulators/create2_emulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

constexpr double kFramePeriodS = 0.015;  // the OI streams every 15 ms
constexpr double kCreate2CountsPerMetre = 508.8 / (std::numbers::pi * 0.072);

// Bytes of arguments after an opcode (OI specification, "Open Interface Commands"); Stream's depend on its first.
std::optional<std::size_t> Arguments(const std::vector<std::uint8_t>& bytes) {
  switch (bytes[0]) {
    case 7:
    case 128:
    case 131:
    case 132:
    case 133:
    case 143:
    case 173: return 0;
    case 150:
    case 142: return 1;
    case 139: return 3;
    case 137:
    case 145:
    case 146: return 4;
    case 148:
    case 149:
      if (bytes.size() < 2) return std::nullopt;  // not yet known
      return 1 + bytes[1];
    default: return 0;  // an opcode not emulated: taken alone, as the robot ignores what it does not know
  }
}

void Big16(std::vector<std::uint8_t>& out, int value) {
  const auto word = static_cast<std::uint16_t>(value);
  out.push_back(static_cast<std::uint8_t>(word >> 8));
  out.push_back(static_cast<std::uint8_t>(word & 0xFF));
}

}  // namespace

Create2Emulator::Create2Emulator(std::filesystem::path link, Pace pace) : terminal_(std::move(link)) {
  if (pace == Pace::kOwner) {
    last_s_ = -1.0;  // counting starts at the first tick
    return;
  }
  last_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

void Create2Emulator::Tick(double now_s) {
  std::lock_guard lock(mutex_);
  if (last_s_ < 0.0) last_s_ = now_s;
  Step(now_s);
}

Create2Emulator::~Create2Emulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

int Create2Emulator::mode() const {
  std::lock_guard lock(mutex_);
  return mode_;
}
std::pair<int, int> Create2Emulator::wheels_mmps() const {
  std::lock_guard lock(mutex_);
  return {left_mmps_, right_mmps_};
}
void Create2Emulator::SetCliff(bool cliff) {
  std::lock_guard lock(mutex_);
  cliff_ = cliff;
}
void Create2Emulator::SetBump(bool bump) {
  std::lock_guard lock(mutex_);
  bump_ = bump;
}
void Create2Emulator::SetBattery(int charge_mah, int capacity_mah, bool on_home_base) {
  std::lock_guard lock(mutex_);
  charge_mah_ = charge_mah;
  capacity_mah_ = capacity_mah;
  home_base_ = on_home_base;
}
void Create2Emulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void Create2Emulator::BadChecksum() {
  std::lock_guard lock(mutex_);
  bad_checksum_ = true;
}
void Create2Emulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void Create2Emulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void Create2Emulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
}
void Create2Emulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  received_.clear();
  mode_ = 0;
  left_mmps_ = right_mmps_ = 0;
  streaming_ = false;
}

void Create2Emulator::Handle(const std::vector<std::uint8_t>& command) {
  switch (command[0]) {
    case 128: mode_ = 1; break;  // Start: Passive
    case 131:
      if (mode_ >= 1) mode_ = 2;
      break;  // Safe
    case 132:
      if (mode_ >= 1) mode_ = 3;
      break;   // Full
    case 7:    // Reset
    case 173:  // Stop: the OI off, the stream too
      mode_ = 0;
      streaming_ = false;
      left_mmps_ = right_mmps_ = 0;
      break;
    case 145:  // Drive Direct: right then left velocity, signed 16-bit big endian, in Safe or Full only
      if (mode_ >= 2) {
        right_mmps_ = std::clamp<int>(static_cast<std::int16_t>(command[1] << 8 | command[2]), -500, 500);
        left_mmps_ = std::clamp<int>(static_cast<std::int16_t>(command[3] << 8 | command[4]), -500, 500);
      }
      break;
    case 148:  // Stream: the packet ids
      if (mode_ >= 1) {
        streamed_.assign(command.begin() + 2, command.end());
        streaming_ = true;
      }
      break;
    case 150: streaming_ = command[1] != 0 && !streamed_.empty(); break;  // Pause/Resume Stream
    default: break;
  }
}

std::vector<std::uint8_t> Create2Emulator::Frame() const {
  std::vector<std::uint8_t> body;
  for (const std::uint8_t id : streamed_) {
    body.push_back(id);
    switch (id) {
      case 7: body.push_back(static_cast<std::uint8_t>(bump_ ? 0x03 : 0x00)); break;
      case 9:
      case 10:
      case 11:
      case 12: body.push_back(cliff_ ? 1 : 0); break;
      case 21: body.push_back(home_base_ ? 2 : 0); break;
      case 22: Big16(body, 14800); break;
      case 23: Big16(body, home_base_ ? 1500 : -900); break;
      case 25: Big16(body, charge_mah_); break;
      case 26: Big16(body, capacity_mah_); break;
      case 34: body.push_back(home_base_ ? 0x02 : 0x00); break;
      case 35: body.push_back(static_cast<std::uint8_t>(mode_)); break;
      case 43: Big16(body, static_cast<int>(std::fmod(std::floor(left_counts_), 65536.0))); break;
      case 44: Big16(body, static_cast<int>(std::fmod(std::floor(right_counts_), 65536.0))); break;
      default: body.pop_back(); break;  // not emulated: left out
    }
  }
  std::vector<std::uint8_t> frame = body;
  frame.insert(frame.begin(), {19, static_cast<std::uint8_t>(body.size())});
  const unsigned sum = std::accumulate(frame.begin(), frame.end(), 0u);
  frame.push_back(static_cast<std::uint8_t>((256 - sum % 256) % 256 + (bad_checksum_ ? 1 : 0)));
  return frame;
}

void Create2Emulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  terminal_.Receive(bytes, 0);
  if (!silent_) received_.insert(received_.end(), bytes.begin(), bytes.end());
  while (!received_.empty()) {
    const std::optional<std::size_t> arguments = Arguments(received_);
    if (!arguments || received_.size() < 1 + *arguments) break;
    const std::vector<std::uint8_t> command(received_.begin(),
                                            received_.begin() + static_cast<std::ptrdiff_t>(1 + *arguments));
    received_.erase(received_.begin(), received_.begin() + static_cast<std::ptrdiff_t>(1 + *arguments));
    Handle(command);
  }
  // Safe mode's own protection: a cliff stops the wheels and leaves the OI in Passive.
  if (mode_ == 2 && cliff_) {
    mode_ = 1;
    left_mmps_ = right_mmps_ = 0;
  }
  const double dt = now_s - last_s_;
  last_s_ = now_s;
  left_counts_ = std::fmod(left_counts_ + left_mmps_ / 1000.0 * dt * kCreate2CountsPerMetre + 65536.0, 65536.0);
  right_counts_ = std::fmod(right_counts_ + right_mmps_ / 1000.0 * dt * kCreate2CountsPerMetre + 65536.0, 65536.0);
  if (!streaming_ || silent_ || now_s < next_frame_s_) return;
  next_frame_s_ = now_s + kFramePeriodS;
  if (!noise_.empty()) {
    terminal_.Send(noise_);
    noise_.clear();
  }
  terminal_.Send(Frame());
  bad_checksum_ = false;
}

void Create2Emulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the robot's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
