#include "testing/emulators/serial_text_emulator.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

constexpr double kPidRateHz = 30.0;
constexpr double kAutoStopS = 2.0;

// A 32-bit signed count from the running total (an AVR `long`, wrapping).
long Count(double counts) {
  return static_cast<long>(static_cast<std::int32_t>(
      static_cast<std::uint32_t>(static_cast<std::int64_t>(std::floor(counts)) & 0xFFFFFFFF)));
}

}  // namespace

SerialTextEmulator::SerialTextEmulator(std::filesystem::path link, SerialTextGeometry geometry, double boot_s)
    : terminal_(std::move(link)), geometry_(geometry), boot_s_(boot_s) {
  last_s_ = NowS();
  booted_s_ = last_s_ + boot_s_;
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

SerialTextEmulator::~SerialTextEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

std::pair<double, double> SerialTextEmulator::wheels_mps() const {
  std::lock_guard lock(mutex_);
  return {left_mps_, right_mps_};
}
int SerialTextEmulator::motor_commands() const {
  std::lock_guard lock(mutex_);
  return motor_commands_;
}
int SerialTextEmulator::invalid_commands() const {
  std::lock_guard lock(mutex_);
  return invalid_commands_;
}
void SerialTextEmulator::Noise(std::string bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void SerialTextEmulator::DropAByte() {
  std::lock_guard lock(mutex_);
  drop_a_byte_ = true;
}
void SerialTextEmulator::LoseReplies(int n) {
  std::lock_guard lock(mutex_);
  replies_to_lose_ = n;
}
void SerialTextEmulator::Slow(double delay_s) {
  std::lock_guard lock(mutex_);
  delay_s_ = delay_s;
}
void SerialTextEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void SerialTextEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void SerialTextEmulator::Restart() {
  std::lock_guard lock(mutex_);
  Boot(NowS());
}
void SerialTextEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
}
void SerialTextEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  Boot(NowS());
}

void SerialTextEmulator::Boot(double now_s) {
  booted_s_ = now_s + boot_s_;
  received_.clear();
  answers_.clear();
  left_mps_ = right_mps_ = 0.0;
  left_counts_ = right_counts_ = 0.0;
}

void SerialTextEmulator::Answer(std::string text, double now_s) {
  answers_.emplace_back(now_s + delay_s_, std::move(text) + "\r\n");
}

void SerialTextEmulator::Handle(const std::string& command, double now_s) {
  std::istringstream in(command);
  char letter = 0;
  in >> letter;
  if (letter == 'e' && in.peek() == std::char_traits<char>::eof()) {
    if (replies_to_lose_ > 0) {
      --replies_to_lose_;
      return;
    }
    std::string counts = std::to_string(Count(left_counts_)) + " " + std::to_string(Count(right_counts_));
    if (drop_a_byte_ && counts.size() > 3) {
      counts.erase(counts.size() / 2 - 1, 1);  // a digit of the left count lost on the line
      drop_a_byte_ = false;
    }
    Answer(std::move(counts), now_s);
    return;
  }
  if (letter == 'm') {
    long left = 0;
    long right = 0;
    if (in >> left >> right) {
      const double metres_per_count = std::numbers::pi * geometry_.wheel_diameter_m / geometry_.counts_per_revolution;
      left_mps_ = static_cast<double>(left) * kPidRateHz * metres_per_count;
      right_mps_ = static_cast<double>(right) * kPidRateHz * metres_per_count;
      last_motor_s_ = now_s;
      ++motor_commands_;
      Answer("OK", now_s);
      return;
    }
  }
  if (letter == 'r' && in.peek() == std::char_traits<char>::eof()) {
    left_counts_ = right_counts_ = 0.0;
    Answer("OK", now_s);
    return;
  }
  if (letter == 'b' && in.peek() == std::char_traits<char>::eof()) {
    Answer("57600", now_s);
    return;
  }
  ++invalid_commands_;
  Answer("Invalid Command", now_s);
}

void SerialTextEmulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  terminal_.Receive(bytes, 0);
  if (!silent_ && now_s >= booted_s_) received_.append(bytes.begin(), bytes.end());
  for (std::size_t end; (end = received_.find('\r')) != std::string::npos;) {
    const std::string command = received_.substr(0, end);
    received_.erase(0, end + 1);
    if (!command.empty()) Handle(command, now_s);
  }
  const double dt = now_s - last_s_;
  last_s_ = now_s;
  if (now_s - last_motor_s_ > kAutoStopS) left_mps_ = right_mps_ = 0.0;
  const double counts_per_metre = geometry_.counts_per_revolution / (std::numbers::pi * geometry_.wheel_diameter_m);
  left_counts_ += left_mps_ * dt * counts_per_metre;
  right_counts_ += right_mps_ * dt * counts_per_metre;
  while (!answers_.empty() && answers_.front().first <= now_s) {
    if (!noise_.empty()) {
      terminal_.Send(std::span(reinterpret_cast<const std::uint8_t*>(noise_.data()), noise_.size()));
      noise_.clear();
    }
    const std::string& text = answers_.front().second;
    if (!silent_) terminal_.Send(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    answers_.pop_front();
  }
}

void SerialTextEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the board's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
