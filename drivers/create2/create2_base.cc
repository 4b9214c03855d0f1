#include "drivers/create2/create2_base.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <spdlog/spdlog.h>

#include "drivers/serial/reconnect.h"
#include "drivers/wheels/command_ramp.h"

namespace corridor::drivers::create2 {
namespace {

// Safe mode is asked for again at most this often while the robot sits in Passive (after a cliff or a dropped
// wheel): the OI takes a moment to change modes.
constexpr double kSafeRetryS = 0.5;

}  // namespace

Create2Base::Create2Base(const Create2Options& options, const Clock& clock)
    : options_(options), clock_(clock), odometry_(options.wheels.Valid() ? options.wheels : kCreate2Wheels) {
  if (options.port.empty()) throw std::invalid_argument("create2: no port given");
  if (!(options.command_timeout_s > 0.0) || !(options.stale_s > 0.0) || !(options.silence_s > options.stale_s) ||
      !(options.reconnect_s > 0.0) || !options.wheels.Valid()) {
    throw std::invalid_argument(
        "create2: timeouts and wheel geometry must be positive, and silence_s longer than stale_s");
  }
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

Create2Base::~Create2Base() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

BaseLimits Create2Base::limits() const {
  return {options_.max_linear_mps, options_.max_angular_rps, options_.max_linear_accel_mps2,
          options_.max_angular_accel_rps2, options_.footprint_radius_m};
}

void Create2Base::SetVelocity(const nav::Twist2& command) {
  std::lock_guard lock(mutex_);
  command_ = {std::clamp(command.linear_mps, -options_.max_linear_mps, options_.max_linear_mps),
              std::clamp(command.angular_rps, -options_.max_angular_rps, options_.max_angular_rps)};
  command_ns_ = clock_.Now();
}

void Create2Base::SetOdometryHandler(OdometryHandler handler) {
  std::lock_guard lock(mutex_);
  odometry_handler_ = std::move(handler);
}

void Create2Base::SetBatteryHandler(BatteryHandler handler) {
  std::lock_guard lock(mutex_);
  battery_handler_ = std::move(handler);
}

Create2Status Create2Base::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void Create2Base::SetLinkHandler(LinkHandler handler) {
  std::lock_guard lock(mutex_);
  link_handler_ = std::move(handler);
}

void Create2Base::SetState(LinkState state, std::string error) {
  ChangeLink(mutex_, status_, link_handler_, "create2", options_.port.string(), state, std::move(error));
}

void Create2Base::Run(std::stop_token stop) {
  RunReconnecting(
      stop, options_.reconnect_s,
      [&] {
        SerialPort port(options_.port, options_.baud_rate);
        Drive(port, stop);
      },
      [&](const std::string& error) { SetState(LinkState::kDisconnected, error); },
      [&] {
        std::lock_guard lock(mutex_);
        ++status_.reconnects;
      });
}

void Create2Base::Drive(SerialPort& port, std::stop_token stop) {
  SetState(LinkState::kConnecting);
  odometry_.Restart();  // the robot may have been power-cycled: its counts start anew
  driven_ = {};
  port.Write(EncodeStart());
  port.Write(EncodeSafe());
  port.Write(EncodeStream(StreamedPackets()));
  StreamParser parser;
  std::vector<SensorFrame> frames;
  std::array<std::uint8_t, 256> buffer{};
  last_frame_ns_ = clock_.Now();
  while (!stop.stop_requested()) {
    const std::size_t n = port.Read(buffer, options_.stale_s);
    frames.clear();
    parser.Push(std::span<const std::uint8_t>(buffer.data(), n), frames);
    {
      std::lock_guard lock(mutex_);
      status_.dropped_frames = parser.dropped();
    }
    for (const SensorFrame& frame : frames) Take(port, frame);
    const double quiet_s = ToSeconds(clock_.Now() - last_frame_ns_);
    if (quiet_s > options_.silence_s) {
      SetState(LinkState::kSilent, fmt::format("no sensor frame for {:.1f} s: restarting the stream", options_.silence_s));
      return;
    }
    if (quiet_s > options_.stale_s) {
      SetState(LinkState::kStale, fmt::format("no sensor frame for {:.0f} ms", quiet_s * 1e3));
      port.Write(EncodeDriveDirect(0, 0));  // the robot keeps its last command: stop it while it may still listen
      driven_ = {};
    }
  }
  port.Write(EncodeDriveDirect(0, 0));
  port.Write(EncodePauseStream(false));
  port.Write(EncodeStop());
}

void Create2Base::Take(SerialPort& port, const SensorFrame& frame) {
  const TimeNs now = clock_.Now();
  const double dt = std::max(1e-3, ToSeconds(now - last_frame_ns_));
  last_frame_ns_ = now;
  if (frame.has_encoders) odometry_.Update(now, frame.left_counts, frame.right_counts);
  // The wheels' command: zero when commands stopped coming or the floor is not there.
  nav::Twist2 target;
  OdometryHandler odometry;
  BatteryHandler battery;
  {
    std::lock_guard lock(mutex_);
    if (ToSeconds(now - command_ns_) <= options_.command_timeout_s) target = command_;
    ++status_.frames;
    status_.oi_mode = frame.oi_mode;
    status_.cliff = frame.cliff;
    status_.wheel_drop = frame.wheel_drop_left || frame.wheel_drop_right;
    odometry = odometry_handler_;
    if (ToSeconds(now - last_battery_ns_) >= options_.battery_period_s) battery = battery_handler_;
  }
  SetState(LinkState::kRunning);
  const bool floor_missing = frame.cliff || frame.wheel_drop_left || frame.wheel_drop_right;
  if (floor_missing) target = {};
  driven_ = RampToward(driven_, target, options_.max_linear_accel_mps2, options_.max_angular_accel_rps2, dt);
  if (floor_missing) driven_ = {};  // at once, not ramped
  const double half_track = 0.5 * options_.wheels.track_m;
  const auto mmps = [](double mps) { return static_cast<int>(std::lround(mps * 1000.0)); };
  port.Write(EncodeDriveDirect(mmps(driven_.linear_mps - half_track * driven_.angular_rps),
                               mmps(driven_.linear_mps + half_track * driven_.angular_rps)));
  // Passive after a safety stop: Safe again once the floor is back.
  if (frame.oi_mode == 1 && !floor_missing && ToSeconds(now - last_safe_ns_) >= kSafeRetryS) {
    port.Write(EncodeSafe());
    last_safe_ns_ = now;
  }
  if (odometry) {
    odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(), frame.bump_left || frame.bump_right,
                           floor_missing});
  }
  if (battery) {
    last_battery_ns_ = now;
    BatteryState state;
    state.stamp_ns = now;
    state.charge = frame.capacity_ah > 0.0 ? std::clamp(frame.charge_ah / frame.capacity_ah, 0.0, 1.0) : 0.0;
    state.voltage_v = frame.voltage_v;
    state.current_a = frame.current_a;
    state.charging = frame.charging_state >= 1 && frame.charging_state <= 3;  // reconditioning, full, trickle
    state.on_charger = frame.on_home_base;
    battery(state);
  }
}

}  // namespace corridor::drivers::create2
