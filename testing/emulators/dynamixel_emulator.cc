#include "testing/emulators/dynamixel_emulator.h"

#include <algorithm>
#include <chrono>

#include "testing/emulators/device_end.h"

namespace corridor::testing {
namespace {

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

// The error numbers of a status packet.
constexpr std::uint8_t kInstructionError = 0x02;
constexpr std::uint8_t kCrcError = 0x03;
constexpr std::uint8_t kDataLengthError = 0x05;
constexpr std::uint8_t kAlert = 0x80;

}  // namespace

DynamixelEmulator::DynamixelEmulator(std::filesystem::path link, std::uint8_t id, std::size_t table_size)
    : table_(table_size, 0), id_(id), terminal_(std::move(link)) {}

void DynamixelEmulator::Start() {
  last_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

void DynamixelEmulator::Stop() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

int DynamixelEmulator::crc_errors() const {
  std::lock_guard lock(mutex_);
  return crc_errors_;
}
int DynamixelEmulator::reboots() const {
  std::lock_guard lock(mutex_);
  return reboots_;
}
void DynamixelEmulator::Noise(std::vector<std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void DynamixelEmulator::BadCrc() {
  std::lock_guard lock(mutex_);
  bad_crc_ = true;
}
void DynamixelEmulator::Slow(double delay_s) {
  std::lock_guard lock(mutex_);
  delay_s_ = delay_s;
}
void DynamixelEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void DynamixelEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void DynamixelEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  terminal_.Unplug();
}
void DynamixelEmulator::Replug() {
  std::lock_guard lock(mutex_);
  terminal_.Plug();
  received_.clear();
  answers_.clear();
  Restarted();
}

std::int32_t DynamixelEmulator::Int32At(std::size_t address) const {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(table_[address]) | table_[address + 1] << 8 |
                                   table_[address + 2] << 16 | static_cast<std::uint32_t>(table_[address + 3]) << 24);
}

void DynamixelEmulator::SetInt32(std::size_t address, std::int32_t value) {
  const auto v = static_cast<std::uint32_t>(value);
  for (std::size_t i = 0; i < 4; ++i) table_[address + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

void DynamixelEmulator::Answer(std::uint8_t error, const std::vector<std::uint8_t>& parameters, double now_s) {
  std::vector<std::uint8_t> body{0x55, static_cast<std::uint8_t>(error | (alert() ? kAlert : 0))};
  for (const std::uint8_t b : parameters) {
    body.push_back(b);
    const std::size_t n = body.size();
    if (n >= 3 && HeaderAt(body, n - 3)) body.push_back(0xFD);  // stuffed
  }
  const std::size_t length = body.size() + 2;
  std::vector<std::uint8_t> packet{
      0xFF, 0xFF, 0xFD, 0x00, id_, static_cast<std::uint8_t>(length & 0xFF), static_cast<std::uint8_t>(length >> 8)};
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

void DynamixelEmulator::Handle(std::uint8_t instruction, const std::vector<std::uint8_t>& parameters, double now_s) {
  const std::size_t address = parameters.size() >= 2 ? (parameters[0] | parameters[1] << 8) : 0;
  switch (instruction) {
    case 0x01:  // Ping: the model number and the firmware's version
      Answer(0, {table_[0], table_[1], 1}, now_s);
      return;
    case 0x02: {  // Read: address, length
      const std::size_t length = parameters.size() == 4 ? (parameters[2] | parameters[3] << 8) : 0;
      if (length == 0 || address + length > table_.size()) {
        Answer(kDataLengthError, {}, now_s);
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
      if (length == 0 || address + length > table_.size()) {
        Answer(kDataLengthError, {}, now_s);
        return;
      }
      const std::span<const std::uint8_t> data(parameters.data() + 2, length);
      if (const std::uint8_t error = Check(address, data); error != 0) {
        Answer(error, {}, now_s);
        return;
      }
      std::copy(parameters.begin() + 2, parameters.end(), table_.begin() + static_cast<std::ptrdiff_t>(address));
      Written(address, length);
      Answer(0, {}, now_s);
      return;
    }
    case 0x08:  // Reboot: answered, then restarted
      Answer(0, {}, now_s);
      ++reboots_;
      Restarted();
      return;
    default: Answer(kInstructionError, {}, now_s);
  }
}

void DynamixelEmulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  terminal_.Receive(bytes, 0);
  if (!silent_) received_.insert(received_.end(), bytes.begin(), bytes.end());
  // Whole instruction packets to this device; what does not begin one is skipped.
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
      if (id == id_) Answer(kCrcError, {}, now_s);
    } else if (id == id_) {
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
  Advance(now_s - last_s_);
  last_s_ = now_s;
  while (!answers_.empty() && answers_.front().first <= now_s) {
    if (!noise_.empty()) {
      terminal_.Send(noise_);
      noise_.clear();
    }
    if (!silent_) terminal_.Send(answers_.front().second);
    answers_.pop_front();
  }
}

void DynamixelEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the device's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
