#include "drivers/hokuyo/hokuyo_laser.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <spdlog/fmt/fmt.h>

namespace corridor::drivers::hokuyo {
namespace {

std::span<const std::uint8_t> Bytes(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

HokuyoLaser::HokuyoLaser(const HokuyoOptions& options, const Clock& clock)
    : LinkedDevice("hokuyo", options.port), options_(options), clock_(clock) {
  if (options.port.empty()) throw std::invalid_argument("hokuyo: no port given");
  if (!(options.stale_s >= 0.0) || !(options.silence_s > options.stale_s) || !(options.reconnect_s > 0.0) ||
      !(options.answer_s > 0.0) || !(options.max_range_m > options.min_range_m)) {
    throw std::invalid_argument(
        "hokuyo: reconnect_s and answer_s must be positive, silence_s longer than stale_s, max_range_m above "
        "min_range_m");
  }
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

HokuyoLaser::~HokuyoLaser() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void HokuyoLaser::SetScanHandler(ScanHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void HokuyoLaser::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] {
    SetState(LinkState::kConnecting);
    const std::unique_ptr<ByteStream> stream = OpenStream(options_.port, options_.baud_rate, options_.answer_s);
    Session(*stream, stop);
  });
}

std::optional<Response> HokuyoLaser::Ask(ByteStream& stream, ResponseReader& reader, const std::string& command) {
  stream.Write(Bytes(command + "\n"));
  std::vector<Response> answers;
  std::array<std::uint8_t, 512> buffer{};
  const TimeNs give_up = clock_.Now() + FromSeconds(options_.answer_s);
  for (TimeNs now = clock_.Now(); now < give_up; now = clock_.Now()) {
    const std::size_t n = stream.Read(buffer, ToSeconds(give_up - now));
    answers.clear();
    reader.Push(std::span<const std::uint8_t>(buffer.data(), n), answers);
    for (Response& answer : answers) {
      if (answer.echo.ends_with(command)) return std::move(answer);  // noise may precede the echo
    }
  }
  return std::nullopt;
}

void HokuyoLaser::Session(ByteStream& stream, std::stop_token stop) {
  ResponseReader reader;
  // A stream left running (by another program, or a session cut short) stops; an older URG starts in SCIP 1.1.
  stream.Write(Bytes("QT\n"));
  Ask(stream, reader, "SCIP2.0");
  const std::optional<Response> pp = Ask(stream, reader, "PP");
  const std::optional<Parameters> parameters = pp ? DecodeParameters(*pp) : std::nullopt;
  if (!parameters) {
    SetState(LinkState::kSilent, pp ? "the parameters (PP) did not add up" : "no answer to PP (SCIP 2.0?)");
    return;
  }
  const std::string md = EncodeMd(parameters->first_step, parameters->last_step);
  const std::string md_command = md.substr(0, md.size() - 1);
  const std::optional<Response> started = Ask(stream, reader, md_command);
  if (!started || (started->status != "00" && started->status != "99")) {  // 99: its first scan already
    SetState(LinkState::kSilent, started ? "MD refused: status " + started->status : "no answer to MD");
    return;
  }
  const double scan_period_s = 60.0 / std::max(1, parameters->scan_rpm);
  const double stale_s = options_.stale_s > 0.0 ? options_.stale_s : 1.5 * scan_period_s + 0.01;
  {
    std::lock_guard lock(mutex_);
    status_.parameters = parameters;
  }
  SetState(LinkState::kRunning);
  std::vector<Response> answers;
  TimeNs last_scan_ns = clock_.Now();
  Stream(
      stream, stop, [&] { return stale_s / 2.0; },
      [&](std::span<const std::uint8_t> bytes, bool) {
        const TimeNs now = clock_.Now();
        answers.clear();
        reader.Push(bytes, answers);
        for (const Response& answer : answers) {
          const std::optional<ScanData> data = DecodeScan(answer);
          if (!data) continue;
          last_scan_ns = now;
          ScanHandler handler;
          {
            std::lock_guard lock(mutex_);
            ++status_.scans;
            handler = handler_;
          }
          SetState(LinkState::kRunning);
          if (handler) handler(std::make_shared<const LaserScan>(ToScan(*parameters, *data, now)));
        }
        {
          std::lock_guard lock(mutex_);
          status_.dropped_answers = reader.dropped();
        }
        const double quiet_s = ToSeconds(now - last_scan_ns);
        if (quiet_s >= options_.silence_s) {
          SetState(LinkState::kSilent, fmt::format("no scan for {:.1f} s: restarting the stream", options_.silence_s));
          return false;
        }
        if (quiet_s >= stale_s) SetState(LinkState::kStale, fmt::format("no scan for {:.0f} ms", stale_s * 1e3));
        return true;
      });
  stream.Write(Bytes("QT\n"));  // the stream and the laser off
}

LaserScan HokuyoLaser::ToScan(const Parameters& p, const ScanData& data, TimeNs stamp_ns) const {
  LaserScan scan;
  scan.stamp_ns = stamp_ns;
  scan.angle_increment_rad = 2.0 * std::numbers::pi / p.steps_per_turn;
  scan.angle_min_rad = (p.first_step - p.front_step) * scan.angle_increment_rad;
  scan.range_min_m = std::max(options_.min_range_m, p.min_range_mm / 1000.0);
  scan.range_max_m = std::min(options_.max_range_m, p.max_range_mm / 1000.0);
  scan.ranges.reserve(data.ranges_mm.size());
  for (const std::uint32_t mm : data.ranges_mm) {
    const double m = mm / 1000.0;
    const bool good = m >= scan.range_min_m && m <= scan.range_max_m;
    scan.ranges.push_back(good ? static_cast<float>(m) : std::numeric_limits<float>::infinity());
  }
  // The device turns counter-clockwise once a scan period and sends a scan as soon as its last step is measured:
  // taken as a whole turn that ends half a step past the last (what it turned through unseen, behind, has no beams).
  scan.sweep_s = 60.0 / std::max(1, p.scan_rpm);
  scan.sweep_clockwise = false;
  scan.sweep_start_rad =
      scan.angle_min_rad + (static_cast<double>(scan.ranges.size()) - 0.5) * scan.angle_increment_rad;
  return scan;
}

}  // namespace corridor::drivers::hokuyo
