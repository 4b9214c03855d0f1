#include "drivers/rplidar/rplidar_laser.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace corridor::drivers::rplidar {

namespace {

// The descriptor answering a request, past any bytes before its start flags; then `length` bytes of response when
// `length` > 0. Nothing when it does not come within timeout_s or is of another type.
std::optional<std::vector<std::uint8_t>> Answer(SerialPort& port, DataType type, std::size_t length, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  const auto left = [&] { return std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count(); };
  std::vector<std::uint8_t> bytes;
  while (true) {
    // Drop what comes before the first A5 5A (keeping a last A5, which may begin one).
    const auto flag = std::adjacent_find(bytes.begin(), bytes.end(), [](std::uint8_t a, std::uint8_t b) {
      return a == kStartFlag1 && b == kStartFlag2;
    });
    if (flag != bytes.end()) {
      bytes.erase(bytes.begin(), flag);
    } else {
      const bool keep_last = !bytes.empty() && bytes.back() == kStartFlag1;
      bytes.erase(bytes.begin(), bytes.end() - (keep_last ? 1 : 0));
    }
    if (bytes.size() >= kDescriptorBytes) break;  // from A5 5A on
    if (left() <= 0.0 || !port.ReadExactly(bytes, bytes.size() + 1, left())) return std::nullopt;
  }
  const std::optional<Descriptor> descriptor =
      DecodeDescriptor(std::span<const std::uint8_t, kDescriptorBytes>(bytes.data(), kDescriptorBytes));
  if (!descriptor || descriptor->type != static_cast<std::uint8_t>(type)) return std::nullopt;
  std::vector<std::uint8_t> response(bytes.begin() + kDescriptorBytes, bytes.end());
  if (length > 0 && response.size() < length && !port.ReadExactly(response, length, std::max(0.0, left()))) {
    return std::nullopt;
  }
  return response;
}

}  // namespace

RplidarLaser::RplidarLaser(const RplidarOptions& options, const Clock& clock)
    : RotatingLaser("rplidar", {options.port, options.stale_s, options.silence_s, options.reconnect_s},
                    options.base_T_laser, options.height_m, options.sweep, clock),
      options_(options) {
  if (!(options.answer_s > 0.0)) throw std::invalid_argument("rplidar: answer_s must be positive");
  thread_ = std::jthread([this](std::stop_token stop) {
    RunPortSessions(stop, options_.baud_rate, [&](SerialPort& port) { Scan(port, stop); });
  });
}

RplidarLaser::~RplidarLaser() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void RplidarLaser::Scan(SerialPort& port, std::stop_token stop) {
  // The A1's motor runs while DTR is clear (its USB adapter inverts it into MOTOCTL); other models ignore DTR. A
  // pseudo-terminal has no modem lines and refuses, which is not an error.
  port.SetDtr(false);
  port.Write(EncodeRequest(Command::kStop));
  port.Drain(0.02);  // what the device was sending before the stop took (a scan under way) is not an answer
  port.Write(EncodeRequest(Command::kGetInfo));
  const auto info = Answer(port, DataType::kInfo, kInfoBytes, options_.answer_s);
  if (!info) {
    SetState(LinkState::kSilent, "no answer to GET_INFO");
    return;
  }
  {
    std::lock_guard lock(mutex_);
    status_.info = DecodeInfo(std::span<const std::uint8_t, kInfoBytes>(info->data(), kInfoBytes));
  }
  port.Write(EncodeRequest(Command::kGetHealth));
  const auto health = Answer(port, DataType::kHealth, kHealthBytes, options_.answer_s);
  if (!health) {
    SetState(LinkState::kSilent, "no answer to GET_HEALTH");
    return;
  }
  const DeviceHealth h = DecodeHealth(std::span<const std::uint8_t, kHealthBytes>(health->data(), kHealthBytes));
  if (h.status == 2) {
    // The protocol's remedy: reset, and start again once it has rebooted.
    SetState(LinkState::kConnecting, "the device reports error " + std::to_string(h.error_code) + ": resetting it");
    port.Write(EncodeRequest(Command::kReset));
    return;
  }
  const bool express = options_.scan_mode == ScanMode::kExpress;
  port.Write(express ? EncodeExpressScanRequest() : EncodeRequest(Command::kScan));
  const auto started = Answer(port, express ? DataType::kCapsule : DataType::kScan, 0, options_.answer_s);
  if (!started) {
    // Firmware before 1.17 knows no express scan and says nothing: the log says what to change.
    SetState(LinkState::kSilent, express ? "no answer to EXPRESS_SCAN (firmware before 1.17 has none: scan: standard)"
                                         : "no answer to SCAN");
    return;
  }
  NodeStream nodes;
  CapsuleStream capsules;
  ReadSweeps(
      port, stop, *started,
      [&](std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& points) -> std::uint64_t {
        if (express) {
          const std::uint64_t before = capsules.capsules();
          capsules.Push(bytes, points);
          return capsules.capsules() - before;
        }
        nodes.Push(bytes, points);
        return points.size();
      },
      [&](RplidarStatus& status) {
        status.skipped_bytes = express ? capsules.skipped_bytes() : nodes.skipped_bytes();
      });
  port.Write(EncodeRequest(Command::kStop));
  port.SetDtr(true);
}

}  // namespace corridor::drivers::rplidar
