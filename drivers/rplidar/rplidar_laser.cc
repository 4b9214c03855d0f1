#include "drivers/rplidar/rplidar_laser.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include <spdlog/spdlog.h>

namespace corridor::drivers::rplidar {

namespace {

constexpr std::chrono::milliseconds kGather{5};

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
    : LinkedDevice("rplidar", options.port.string()), options_(options), clock_(clock) {
  if (options.port.empty()) throw std::invalid_argument("rplidar: no port given");
  if (!(options.stale_s > 0.0) || !(options.silence_s > options.stale_s) || !(options.reconnect_s > 0.0) ||
      !(options.answer_s > 0.0)) {
    throw std::invalid_argument(
        "rplidar: stale_s, reconnect_s and answer_s must be positive, and silence_s longer than stale_s");
  }
  SweepAssembler check(options.sweep);  // throws for bad sweep options here, not on the thread
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

RplidarLaser::~RplidarLaser() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void RplidarLaser::SetScanHandler(ScanHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void RplidarLaser::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] {
    SerialPort port(options_.port, options_.baud_rate);
    Scan(port, stop);
  });
}

void RplidarLaser::Scan(SerialPort& port, std::stop_token stop) {
  SetState(LinkState::kConnecting);
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
  port.Write(EncodeRequest(Command::kScan));
  const auto started = Answer(port, DataType::kScan, 0, options_.answer_s);
  if (!started) {
    SetState(LinkState::kSilent, "no answer to SCAN");
    return;
  }
  NodeStream stream;
  SweepAssembler sweeps(options_.sweep);
  std::vector<Node> nodes;
  const auto take = [&](std::span<const std::uint8_t> bytes) {
    nodes.clear();
    stream.Push(bytes, nodes);
    for (const Node& node : nodes) {
      std::optional<LaserScan> scan = sweeps.Add(node, clock_.Now());
      if (!scan) continue;
      ScanHandler handler;
      {
        std::lock_guard lock(mutex_);
        ++status_.scans;
        status_.skipped_bytes = stream.skipped_bytes();
        handler = handler_;
      }
      if (handler) handler(std::make_shared<const LaserScan>(std::move(*scan)));
    }
  };
  take(*started);  // nodes that came with the descriptor
  SetState(LinkState::kRunning);
  std::array<std::uint8_t, 1024> buffer{};
  TimeNs last_byte_ns = clock_.Now();
  while (!stop.stop_requested()) {
    const std::size_t n = port.Read(buffer, options_.stale_s);
    const TimeNs now = clock_.Now();
    if (n == 0) {
      const double quiet_s = ToSeconds(now - last_byte_ns);
      if (quiet_s >= options_.silence_s) {
        SetState(LinkState::kSilent, fmt::format("no data for {:.1f} s: restarting the scan", options_.silence_s));
        return;
      }
      if (quiet_s >= options_.stale_s) SetState(LinkState::kStale, fmt::format("no data for {:.0f} ms", options_.stale_s * 1e3));
      continue;
    }
    last_byte_ns = now;
    SetState(LinkState::kRunning);
    take(std::span<const std::uint8_t>(buffer.data(), n));
    // A few bytes came (a USB adapter passes them on every millisecond or so): let more gather before the next read,
    // rather than wake a thousand times a second. A revolution ends at most kGather later.
    if (n < buffer.size() / 4) std::this_thread::sleep_for(kGather);
  }
  port.Write(EncodeRequest(Command::kStop));
  port.SetDtr(true);
}

}  // namespace corridor::drivers::rplidar
