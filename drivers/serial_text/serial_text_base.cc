#include "drivers/serial_text/serial_text_base.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace corridor::drivers::serial_text {
namespace {

// Counts that changed by more than the wheels could turn at this many times the top speed, and a few counts of
// play, are not believed.
constexpr double kPlausibleSpeedFactor = 2.0;
constexpr double kPlausibleSlackCounts = 20.0;
// This many unbelievable replies in a row: the board counts anew (it restarted without the port closing).
constexpr int kRestartAfter = 3;
// While the board boots, the counts are asked for this often.
constexpr double kBootPollS = 0.2;
// Asks kept waiting for their answers: a second of them at the usual rate (replies lost to noise leave theirs behind).
constexpr std::size_t kAsksKept = 32;

std::span<const std::uint8_t> Bytes(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

SerialTextBase::SerialTextBase(const SerialTextOptions& options, const Clock& clock)
    : SerialBase("serial-text", options, clock) {
  if (!(options.pid_rate_hz > 0.0) || !(options.poll_period_s > 0.0) || !(options.boot_s > 0.0)) {
    throw std::invalid_argument("serial-text: pid_rate_hz, poll_period_s and boot_s must be positive");
  }
  Start();
}

SerialTextBase::~SerialTextBase() { StopThread(); }

void SerialTextBase::Session(SerialPort& port, std::stop_token stop) {
  Begin();
  last_counts_.reset();
  asks_.clear();
  implausible_run_ = 0;
  LineSplitter lines;
  AwaitBoard(port, lines, stop);
  const std::string stop_wheels = EncodeMotorSpeeds(0, 0);
  TimeNs next_ask_ns = clock_.Now();
  // Each pass takes the replies that came (a slow board's answer is taken in a later pass), and asks again when due.
  Stream(
      port, stop, [&] { return std::max(1e-3, ToSeconds(next_ask_ns - clock_.Now())); },
      [&](std::span<const std::uint8_t> bytes, bool) {
        Handle(port, lines, bytes);
        if (Due(next_ask_ns, clock_.Now(), options_.poll_period_s)) Ask(port);
        return Watch(port, Bytes(stop_wheels), "encoder reply");
      });
  port.Write(Bytes(stop_wheels));
}

void SerialTextBase::AwaitBoard(SerialPort& port, LineSplitter& lines, std::stop_token stop) {
  const TimeNs give_up = clock_.Now() + FromSeconds(options_.boot_s);
  std::vector<std::string> got;
  std::array<std::uint8_t, 256> buffer{};
  while (!stop.stop_requested()) {
    const TimeNs now = clock_.Now();
    if (now >= give_up) {
      throw std::runtime_error(
          fmt::format("no answer to 'e' within {:.1f} s (a ROSArduinoBridge-class board at {} baud?)", options_.boot_s,
                      options_.baud_rate));
    }
    Ask(port);
    const std::size_t n = port.Read(buffer, std::min(kBootPollS, ToSeconds(give_up - now)));
    got.clear();
    lines.Push(std::span<const std::uint8_t>(buffer.data(), n), got);
    for (const std::string& line : got) {
      if (const std::optional<EncoderCounts> counts = ParseEncoders(line)) {
        // Where counting starts; the stream is watched from here on. The answer is to the last ask: those before it
        // went to a board still booting.
        const TimeNs at = clock_.Now();
        last_counts_ = counts;
        last_counts_asked_ns_ = asks_.empty() ? at : asks_.back();
        asks_.clear();
        Reported(at);
        odometry_.Update(last_counts_asked_ns_, static_cast<std::uint16_t>(counts->left),
                         static_cast<std::uint16_t>(counts->right));
        return;
      }
    }
  }
}

void SerialTextBase::Handle(SerialPort& port, LineSplitter& lines, std::span<const std::uint8_t> bytes) {
  std::vector<std::string> got;
  std::uint64_t bad = static_cast<std::uint64_t>(lines.Push(bytes, got));
  for (const std::string& line : got) {
    if (const std::optional<EncoderCounts> counts = ParseEncoders(line)) {
      Take(port, *counts);
    } else if (line != "OK") {
      ++bad;
    }
  }
  if (bad == 0) return;
  std::lock_guard lock(mutex_);
  status_.bad_lines += bad;
}

void SerialTextBase::Ask(SerialPort& port) {
  port.Write(Bytes(kReadEncoders));
  asks_.push_back(clock_.Now());
  if (asks_.size() > kAsksKept) asks_.pop_front();
}

TimeNs SerialTextBase::Answered(TimeNs now) {
  if (asks_.empty()) return now;
  const TimeNs asked = asks_.front();
  asks_.pop_front();
  return asked;
}

void SerialTextBase::Take(SerialPort& port, const EncoderCounts& counts) {
  const TimeNs now = clock_.Now();
  const TimeNs asked = Answered(now);
  // Believable only if neither wheel turned further than it can since the counts before were asked for.
  const double top_mps = options_.max_linear_mps + options_.max_angular_rps * 0.5 * options_.wheels.track_m;
  const double limit = kPlausibleSpeedFactor * top_mps * ToSeconds(now - last_counts_asked_ns_) * CountsPerMetre() +
                       kPlausibleSlackCounts;
  const bool believable = !last_counts_ || (std::abs(CountsChange(last_counts_->left, counts.left)) <= limit &&
                                            std::abs(CountsChange(last_counts_->right, counts.right)) <= limit);
  if (!believable && ++implausible_run_ < kRestartAfter) {
    std::lock_guard lock(mutex_);
    ++status_.implausible;
    return;
  }
  if (!believable) {
    odometry_.Restart();  // the pose stays; counting starts here
    std::lock_guard lock(mutex_);
    ++status_.implausible;
    ++status_.restarts;
  }
  implausible_run_ = 0;
  last_counts_ = counts;
  last_counts_asked_ns_ = asked;
  Reported(now);
  // The velocity is over the time between the questions, not between the takings: the board answers when asked, and a
  // late control loop takes two answers together. The report keeps the taking's time: a reply lost to noise leaves
  // its ask behind, and every later reply is paired with an ask a poll before its own (which the velocity's
  // differences do not see, and a report's stamp would).
  // The low 16 bits: the odometry's wrap-around arithmetic holds for any count width.
  odometry_.Update(asked, static_cast<std::uint16_t>(counts.left), static_cast<std::uint16_t>(counts.right));
  nav::Twist2 target;
  OdometryHandler odometry;
  {
    std::lock_guard lock(mutex_);
    target = CommandAt(now);
    ++status_.replies;
    odometry = odometry_handler_;
  }
  SetState(LinkState::kRunning);
  const nav::Twist2& driven = Drive(target, false, now);
  const double half_track = 0.5 * options_.wheels.track_m;
  const std::string command = EncodeMotorSpeeds(CountsPerFrame(driven.linear_mps - half_track * driven.angular_rps),
                                                CountsPerFrame(driven.linear_mps + half_track * driven.angular_rps));
  port.Write(Bytes(command));
  if (odometry) odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(), false, false});
}

double SerialTextBase::CountsPerMetre() const {
  return options_.wheels.counts_per_revolution / (std::numbers::pi * options_.wheels.wheel_diameter_m);
}

int SerialTextBase::CountsPerFrame(double mps) const {
  return static_cast<int>(std::lround(mps * CountsPerMetre() / options_.pid_rate_hz));
}

}  // namespace corridor::drivers::serial_text
