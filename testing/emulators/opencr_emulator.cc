#include "testing/emulators/opencr_emulator.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

constexpr std::uint8_t kId = 200;
constexpr double kTicksPerMetre = 4096.0 / (std::numbers::pi * 0.066);
constexpr double kOpenCrTrackM = 0.160;
constexpr double kVelocityUnitMps = 0.229 / 60.0 * std::numbers::pi * 0.066;  // 0.229 rpm of a 66 mm wheel
// The control table's addresses (the e-Manual's TurtleBot 3 OpenCR table).
constexpr std::size_t kModelNumber = 0;
constexpr std::size_t kHeartbeat = 19;
constexpr std::size_t kBumper1 = 28;
constexpr std::size_t kBatteryVoltage = 42;
constexpr std::size_t kBatteryPercentage = 46;
constexpr std::size_t kPresentVelocityLeft = 128;
constexpr std::size_t kPresentVelocityRight = 132;
constexpr std::size_t kPresentPositionLeft = 136;
constexpr std::size_t kPresentPositionRight = 140;
constexpr std::size_t kTorqueEnable = 149;
constexpr std::size_t kCmdLinearX = 150;
constexpr std::size_t kCmdAngularZ = 170;
constexpr std::size_t kTableEnd = 182;  // past the profile accelerations
constexpr std::uint16_t kModel = 0x5000;

// CRC-16, polynomial 0x8005, bit by bit as the protocol's document defines it.
std::uint16_t Crc(const std::vector<std::uint8_t>& bytes, std::size_t count) {
  std::uint16_t crc = 0;
  for (std::size_t i = 0; i < count; ++i) {
    crc ^= static_cast<std::uint16_t>(bytes[i] << 8);
    for (int bit = 0; bit < 8; ++bit) crc = static_cast<std::uint16_t>(crc & 0x8000 ? (crc << 1) ^ 0x8005 : crc << 1);
  }
  return crc;
}

bool HeaderAt(const std::vector<std::uint8_t>& b, std::size_t i) {
  return b[i] == 0xFF && b[i + 1] == 0xFF && b[i + 2] == 0xFD;
}

}  // namespace

OpenCrEmulator::OpenCrEmulator(std::filesystem::path link) : terminal_(std::move(link)) {
  table_[kModelNumber] = kModel & 0xFF;
  table_[kModelNumber + 1] = kModel >> 8;
  SetInt32(kBatteryVoltage, 1190);
  SetInt32(kBatteryPercentage, 8000);
  last_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

OpenCrEmulator::~OpenCrEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

std::pair<double, double> OpenCrEmulator::wheels_mps() const {
  std::lock_guard lock(mutex_);
  return {left_mps_, right_mps_};
}
bool OpenCrEmulator::torque() const {
  std::lock_guard lock(mutex_);
  return table_[kTorqueEnable] != 0;
}
int OpenCrEmulator::heartbeats() const {
  std::lock_guard lock(mutex_);
  return heartbeats_;
}
int OpenCrEmulator::crc_errors() const {
  std::lock_guard lock(mutex_);
  return crc_errors_;
}
void OpenCrEmulator::SetBumper(bool pressed) {
  std::lock_guard lock(mutex_);
  table_[kBumper1] = pressed ? 1 : 0;
}
void OpenCrEmulator::SetBattery(double volts, double percent) {
  std::lock_guard lock(mutex_);
  SetInt32(kBatteryVoltage, static_cast<std::int32_t>(std::lround(volts * 100.0)));
  SetInt32(kBatteryPercentage, static_cast<std::int32_t>(std::lround(percent * 100.0)));
}
void OpenCrEmulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void OpenCrEmulator::BadCrc() {
  std::lock_guard lock(mutex_);
  bad_crc_ = true;
}
void OpenCrEmulator::Slow(double delay_s) {
  std::lock_guard lock(mutex_);
  delay_s_ = delay_s;
}
void OpenCrEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void OpenCrEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void OpenCrEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
}
void OpenCrEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  received_.clear();
  answers_.clear();
  table_[kTorqueEnable] = 0;
  for (std::size_t a = kCmdLinearX; a < kCmdAngularZ + 4; ++a) table_[a] = 0;
}

std::int32_t OpenCrEmulator::Int32At(std::size_t address) const {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(table_[address]) | table_[address + 1] << 8 |
                                   table_[address + 2] << 16 | static_cast<std::uint32_t>(table_[address + 3]) << 24);
}

void OpenCrEmulator::SetInt32(std::size_t address, std::int32_t value) {
  const auto v = static_cast<std::uint32_t>(value);
  for (std::size_t i = 0; i < 4; ++i) table_[address + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

void OpenCrEmulator::Answer(std::uint8_t error, const std::vector<std::uint8_t>& parameters, double now_s) {
  std::vector<std::uint8_t> body{0x55, error};
  for (const std::uint8_t b : parameters) {
    body.push_back(b);
    const std::size_t n = body.size();
    if (n >= 3 && HeaderAt(body, n - 3)) body.push_back(0xFD);  // stuffed
  }
  const std::size_t length = body.size() + 2;
  std::vector<std::uint8_t> packet{
      0xFF, 0xFF, 0xFD, 0x00, kId, static_cast<std::uint8_t>(length & 0xFF), static_cast<std::uint8_t>(length >> 8)};
  packet.insert(packet.end(), body.begin(), body.end());
  std::uint16_t crc = Crc(packet, packet.size());
  if (bad_crc_) {
    crc ^= 0x5A5A;
    bad_crc_ = false;
  }
  packet.push_back(crc & 0xFF);
  packet.push_back(crc >> 8);
  answers_.emplace_back(now_s + delay_s_, std::move(packet));
}

void OpenCrEmulator::Handle(std::uint8_t instruction, const std::vector<std::uint8_t>& parameters, double now_s) {
  const std::size_t address = parameters.size() >= 2 ? (parameters[0] | parameters[1] << 8) : 0;
  switch (instruction) {
    case 0x01:  // Ping: the model number and the firmware's version
      Answer(0, {table_[kModelNumber], table_[kModelNumber + 1], 1}, now_s);
      return;
    case 0x02: {  // Read: address, length
      const std::size_t length = parameters.size() == 4 ? (parameters[2] | parameters[3] << 8) : 0;
      if (length == 0 || address + length > kTableEnd) {
        Answer(0x05, {}, now_s);  // data length error
        return;
      }
      Answer(0,
             std::vector<std::uint8_t>(table_.begin() + static_cast<std::ptrdiff_t>(address),
                                       table_.begin() + static_cast<std::ptrdiff_t>(address + length)),
             now_s);
      return;
    }
    case 0x03: {  // Write: address, data
      const std::size_t length = parameters.size() - std::min<std::size_t>(2, parameters.size());
      if (length == 0 || address + length > kTableEnd) {
        Answer(0x05, {}, now_s);
        return;
      }
      std::copy(parameters.begin() + 2, parameters.end(), table_.begin() + static_cast<std::ptrdiff_t>(address));
      if (address <= kHeartbeat && kHeartbeat < address + length) ++heartbeats_;
      Answer(0, {}, now_s);
      return;
    }
    default: Answer(0x02, {}, now_s);  // instruction error
  }
}

void OpenCrEmulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  terminal_.Receive(bytes, 0);
  if (!silent_) received_.insert(received_.end(), bytes.begin(), bytes.end());
  // Whole instruction packets to this board; what does not begin one is skipped.
  while (received_.size() >= 10) {
    if (!HeaderAt(received_, 0) || received_[3] != 0x00) {
      received_.erase(received_.begin());
      continue;
    }
    const std::size_t length = received_[5] | received_[6] << 8;
    if (length < 3 || length > 512) {
      received_.erase(received_.begin());
      continue;
    }
    if (received_.size() < 7 + length) break;
    const std::uint16_t crc = static_cast<std::uint16_t>(received_[5 + length] | received_[6 + length] << 8);
    const std::uint8_t id = received_[4];
    if (Crc(received_, 5 + length) != crc) {
      ++crc_errors_;
      if (id == kId) Answer(0x03, {}, now_s);  // CRC error
    } else if (id == kId) {
      std::vector<std::uint8_t> parameters;
      for (std::size_t i = 8; i < 5 + length; ++i) {
        parameters.push_back(received_[i]);
        const std::size_t n = parameters.size();
        if (n >= 3 && HeaderAt(parameters, n - 3) && i + 1 < 5 + length && received_[i + 1] == 0xFD) ++i;  // stuffed
      }
      Handle(received_[7], parameters, now_s);
    }
    received_.erase(received_.begin(), received_.begin() + static_cast<std::ptrdiff_t>(7 + length));
  }
  // The wheels, as the velocity command says while the torque is on.
  const bool driven = table_[kTorqueEnable] != 0;
  const double v = driven ? Int32At(kCmdLinearX) / 100.0 : 0.0;
  const double w = driven ? Int32At(kCmdAngularZ) / 100.0 : 0.0;
  left_mps_ = v - w * kOpenCrTrackM / 2.0;
  right_mps_ = v + w * kOpenCrTrackM / 2.0;
  const double dt = now_s - last_s_;
  last_s_ = now_s;
  left_ticks_ += left_mps_ * dt * kTicksPerMetre;
  right_ticks_ += right_mps_ * dt * kTicksPerMetre;
  const auto wrapped = [](double ticks) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(std::floor(ticks))));
  };
  SetInt32(kPresentPositionLeft, wrapped(left_ticks_));
  SetInt32(kPresentPositionRight, wrapped(right_ticks_));
  SetInt32(kPresentVelocityLeft, static_cast<std::int32_t>(std::lround(left_mps_ / kVelocityUnitMps)));
  SetInt32(kPresentVelocityRight, static_cast<std::int32_t>(std::lround(right_mps_ / kVelocityUnitMps)));
  while (!answers_.empty() && answers_.front().first <= now_s) {
    if (!noise_.empty()) {
      terminal_.Send(noise_);
      noise_.clear();
    }
    if (!silent_) terminal_.Send(answers_.front().second);
    answers_.pop_front();
  }
}

void OpenCrEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the board's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
