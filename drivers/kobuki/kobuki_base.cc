#include "drivers/kobuki/kobuki_base.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

#include <spdlog/spdlog.h>

#include "drivers/serial/reconnect.h"
#include "drivers/wheels/command_ramp.h"

namespace corridor::drivers::kobuki {

KobukiBase::KobukiBase(const KobukiOptions& options, const Clock& clock)
    : options_(options), clock_(clock), odometry_(options.wheels.Valid() ? options.wheels : kKobukiWheels) {
  if (options.port.empty()) throw std::invalid_argument("kobuki: no port given");
  if (!(options.command_timeout_s > 0.0) || !(options.stale_s > 0.0) || !(options.silence_s > options.stale_s) ||
      !(options.reconnect_s > 0.0) || !options.wheels.Valid() ||
      !(options.battery_full_v > options.battery_empty_v)) {
    throw std::invalid_argument(
        "kobuki: timeouts and wheel geometry must be positive, silence_s longer than stale_s, and the battery full "
        "above empty");
  }
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

KobukiBase::~KobukiBase() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

BaseLimits KobukiBase::limits() const {
  return {options_.max_linear_mps, options_.max_angular_rps, options_.max_linear_accel_mps2,
          options_.max_angular_accel_rps2, options_.footprint_radius_m};
}

void KobukiBase::SetVelocity(const nav::Twist2& command) {
  std::lock_guard lock(mutex_);
  command_ = {std::clamp(command.linear_mps, -options_.max_linear_mps, options_.max_linear_mps),
              std::clamp(command.angular_rps, -options_.max_angular_rps, options_.max_angular_rps)};
  command_ns_ = clock_.Now();
}

void KobukiBase::SetOdometryHandler(OdometryHandler handler) {
  std::lock_guard lock(mutex_);
  odometry_handler_ = std::move(handler);
}

void KobukiBase::SetBatteryHandler(BatteryHandler handler) {
  std::lock_guard lock(mutex_);
  battery_handler_ = std::move(handler);
}

KobukiStatus KobukiBase::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void KobukiBase::SetLinkHandler(LinkHandler handler) {
  std::lock_guard lock(mutex_);
  link_handler_ = std::move(handler);
}

void KobukiBase::SetState(LinkState state, std::string error) {
  ChangeLink(mutex_, status_, link_handler_, "kobuki", options_.port.string(), state, std::move(error));
}

void KobukiBase::Run(std::stop_token stop) {
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

void KobukiBase::Drive(SerialPort& port, std::stop_token stop) {
  SetState(LinkState::kConnecting);
  odometry_.Restart();  // the Kobuki may have been power-cycled: its counts start anew
  driven_ = {};
  PacketParser parser;
  std::vector<FeedbackPacket> packets;
  std::array<std::uint8_t, 256> buffer{};
  last_report_ns_ = clock_.Now();
  while (!stop.stop_requested()) {
    const std::size_t n = port.Read(buffer, options_.stale_s);
    packets.clear();
    parser.Push(std::span<const std::uint8_t>(buffer.data(), n), packets);
    {
      std::lock_guard lock(mutex_);
      status_.dropped_packets = parser.dropped();
    }
    for (const FeedbackPacket& packet : packets) {
      if (packet.sensors) Take(port, *packet.sensors);
    }
    const double quiet_s = ToSeconds(clock_.Now() - last_report_ns_);
    if (quiet_s > options_.silence_s) {
      SetState(LinkState::kSilent, fmt::format("no feedback for {:.1f} s: opening the port anew", options_.silence_s));
      return;
    }
    if (quiet_s > options_.stale_s) {
      SetState(LinkState::kStale, fmt::format("no feedback for {:.0f} ms", quiet_s * 1e3));
      port.Write(EncodeBaseControl({}));  // the Kobuki keeps its last command: stop it while it may still listen
      driven_ = {};
    }
  }
  port.Write(EncodeBaseControl({}));
}

void KobukiBase::Take(SerialPort& port, const SensorData& sensors) {
  const TimeNs now = clock_.Now();
  const double dt = std::max(1e-3, ToSeconds(now - last_report_ns_));
  last_report_ns_ = now;
  odometry_.Update(now, sensors.left_counts, sensors.right_counts);
  // The wheels' command: zero when commands stopped coming or the floor is not there.
  nav::Twist2 target;
  OdometryHandler odometry;
  BatteryHandler battery;
  const bool floor_missing = sensors.cliff || sensors.wheel_drop_left || sensors.wheel_drop_right;
  {
    std::lock_guard lock(mutex_);
    if (ToSeconds(now - command_ns_) <= options_.command_timeout_s) target = command_;
    ++status_.packets;
    status_.cliff = sensors.cliff;
    status_.wheel_drop = sensors.wheel_drop_left || sensors.wheel_drop_right;
    odometry = odometry_handler_;
    if (ToSeconds(now - last_battery_ns_) >= options_.battery_period_s) battery = battery_handler_;
  }
  SetState(LinkState::kRunning);
  driven_ = floor_missing ? nav::Twist2{}  // at once, not ramped
                          : RampToward(driven_, target, options_.max_linear_accel_mps2,
                                       options_.max_angular_accel_rps2, dt);
  port.Write(EncodeBaseControl(ToBaseControl(driven_, options_.wheels.track_m)));
  if (odometry) {
    odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(),
                           sensors.bump_left || sensors.bump_centre || sensors.bump_right, floor_missing});
  }
  if (battery) {
    last_battery_ns_ = now;
    BatteryState state;
    state.stamp_ns = now;
    state.charge = std::clamp((sensors.battery_v - options_.battery_empty_v) /
                                  (options_.battery_full_v - options_.battery_empty_v),
                              0.0, 1.0);
    state.voltage_v = sensors.battery_v;
    state.charging = Charging(sensors.charger);
    state.on_charger = OnDock(sensors.charger);
    battery(state);
  }
}

}  // namespace corridor::drivers::kobuki
