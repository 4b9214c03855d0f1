#include "drivers/lds/lds_laser.h"

#include <array>
#include <chrono>
#include <stdexcept>
#include <vector>

#include <spdlog/fmt/fmt.h>

namespace corridor::drivers::lds {
namespace {

// A few bytes came (a USB adapter passes them on every millisecond or so): more gather before the next read, rather
// than the thread waking a thousand times a second. A revolution ends at most this much later.
constexpr std::chrono::milliseconds kGather{5};

}  // namespace

LdsLaser::LdsLaser(const LdsOptions& options, const Clock& clock)
    : LinkedDevice("lds", options.port.string()), options_(options), clock_(clock) {
  if (options.port.empty()) throw std::invalid_argument("lds: no port given");
  if (!(options.stale_s > 0.0) || !(options.silence_s > options.stale_s) || !(options.reconnect_s > 0.0)) {
    throw std::invalid_argument("lds: stale_s and reconnect_s must be positive, and silence_s longer than stale_s");
  }
  SweepAssembler check(options.sweep);  // throws for bad sweep options here, not on the thread
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

LdsLaser::~LdsLaser() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void LdsLaser::SetScanHandler(ScanHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void LdsLaser::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] {
    SetState(LinkState::kConnecting);
    SerialPort port(options_.port, options_.baud_rate);
    Scan(port, stop);
  });
}

void LdsLaser::Scan(SerialPort& port, std::stop_token stop) {
  const bool lds01 = options_.model == Model::kLds01;
  if (lds01) port.Write(std::array<std::uint8_t, 1>{kLfcdStartCommand});
  PacketStream packets(options_.model);
  SweepAssembler sweeps(options_.sweep);
  std::vector<SweepPoint> points;
  std::array<std::uint8_t, 1024> buffer{};
  TimeNs last_packet_ns = clock_.Now();
  while (!stop.stop_requested()) {
    const std::size_t n = port.Read(buffer, options_.stale_s);
    const TimeNs now = clock_.Now();
    const std::uint64_t packets_before = packets.packets();
    points.clear();
    packets.Push(std::span<const std::uint8_t>(buffer.data(), n), points);
    for (const SweepPoint& point : points) {
      std::optional<LaserScan> scan = sweeps.Add(point, now);
      if (!scan) continue;
      ScanHandler handler;
      {
        std::lock_guard lock(mutex_);
        ++status_.scans;
        handler = handler_;
      }
      if (handler) handler(std::make_shared<const LaserScan>(std::move(*scan)));
    }
    {
      std::lock_guard lock(mutex_);
      status_.packets = packets.packets();
      status_.skipped_bytes = packets.skipped_bytes();
      status_.speed_deg_s = packets.speed_deg_s();
    }
    // Bytes that are all noise are no data: the link is running while packets that check come.
    if (packets.packets() > packets_before) {
      last_packet_ns = now;
      SetState(LinkState::kRunning);
    }
    const double quiet_s = ToSeconds(now - last_packet_ns);
    if (quiet_s >= options_.silence_s) {
      SetState(LinkState::kSilent, fmt::format("no packet for {:.1f} s: opening the port again", options_.silence_s));
      return;
    }
    if (quiet_s >= options_.stale_s) {
      SetState(LinkState::kStale, fmt::format("no packet for {:.0f} ms", options_.stale_s * 1e3));
    }
    if (n > 0 && n < buffer.size() / 4) std::this_thread::sleep_for(kGather);
  }
  if (lds01) port.Write(std::array<std::uint8_t, 1>{kLfcdStopCommand});
}

}  // namespace corridor::drivers::lds
