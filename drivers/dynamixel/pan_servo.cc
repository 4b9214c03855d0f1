#include "drivers/dynamixel/pan_servo.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/fmt/fmt.h>

#include "drivers/dynamixel/dynamixel_link.h"
#include "drivers/dynamixel/x_series_table.h"

namespace corridor::drivers::dynamixel {
namespace {

constexpr double kToRad = std::numbers::pi / 180.0;
// While the servo is awaited, it is pinged this often; answers during set-up are awaited this long.
constexpr double kPingPeriodS = 0.2;
constexpr double kAnswerS = 0.1;

const PanServoOptions& Checked(const PanServoOptions& o) {
  if (o.port.empty()) throw std::invalid_argument("dynamixel pan servo: no port given");
  if (o.id < 0 || o.id > 252) throw std::invalid_argument("dynamixel pan servo: id must be 0-252");
  if (o.center_position < 0 || o.center_position > 4095) {
    throw std::invalid_argument("dynamixel pan servo: center_position must be 0-4095");
  }
  if (!(o.min_deg <= 0.0 && o.max_deg >= 0.0 && o.max_deg - o.min_deg <= 360.0)) {
    throw std::invalid_argument("dynamixel pan servo: need min_deg <= 0 <= max_deg, at most a turn apart");
  }
  if (!(o.max_speed_dps > 0.0) || !(o.max_accel_dps2 > 0.0) || !(o.poll_period_s > 0.0) || !(o.goal_refresh_s > 0.0) ||
      !(o.connect_s > 0.0) || !(o.stale_s > 0.0) || !(o.silence_s > o.stale_s) || !(o.reconnect_s > 0.0)) {
    throw std::invalid_argument(
        "dynamixel pan servo: speeds, periods and timeouts must be positive, silence_s longer than stale_s");
  }
  return o;
}

std::vector<std::uint8_t> WriteInt32(std::uint8_t id, std::uint16_t address, std::int32_t value) {
  std::vector<std::uint8_t> data;
  AppendInt32(data, value);
  return EncodeWrite(id, address, data);
}

std::vector<std::uint8_t> WriteByte(std::uint8_t id, std::uint16_t address, std::uint8_t value) {
  const std::array<std::uint8_t, 1> data{value};
  return EncodeWrite(id, address, data);
}

}  // namespace

DynamixelPanServo::DynamixelPanServo(const PanServoOptions& options, const Clock& clock)
    : LinkedDevice("dynamixel pan servo", options.port.string()),
      options_(Checked(options)),
      clock_(clock),
      id_(static_cast<std::uint8_t>(options.id)) {
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

DynamixelPanServo::~DynamixelPanServo() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

PanLimits DynamixelPanServo::pan_limits() const {
  return {options_.min_deg * kToRad, options_.max_deg * kToRad, options_.max_speed_dps * kToRad};
}

void DynamixelPanServo::SetTarget(double pan_rad) {
  const PanLimits l = pan_limits();
  std::lock_guard lock(mutex_);
  if (std::isfinite(pan_rad)) target_rad_ = std::clamp(pan_rad, l.min_rad, l.max_rad);
}

void DynamixelPanServo::SetReadingHandler(ReadingHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

double DynamixelPanServo::ToPan(std::int32_t position) const {
  const double turned = (position - options_.center_position) * x_series::kRadPerCount;
  return options_.reversed ? -turned : turned;
}

std::int32_t DynamixelPanServo::ToPosition(double pan_rad) const {
  const double counts = (options_.reversed ? -pan_rad : pan_rad) / x_series::kRadPerCount;
  return options_.center_position + static_cast<std::int32_t>(std::lround(counts));
}

void DynamixelPanServo::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] {
    SerialPort port(options_.port, options_.baud_rate);
    Session(port, stop);
  });
}

void DynamixelPanServo::Session(SerialPort& port, std::stop_token stop) {
  namespace address = x_series::address;
  SetState(LinkState::kConnecting);
  StatusParser parser;
  // The servo, found by a ping (its answer: the model number and the firmware's version).
  Answer pong;
  for (const TimeNs give_up = clock_.Now() + FromSeconds(options_.connect_s); !pong.status && !stop.stop_requested();) {
    if (clock_.Now() >= give_up) {
      throw std::runtime_error(fmt::format("no answer to a ping of servo {} within {:.1f} s (at {} baud?)", options_.id,
                                           options_.connect_s, options_.baud_rate));
    }
    pong = Transact(port, parser, clock_, id_, EncodePing(id_), 3, kPingPeriodS);
  }
  if (!pong.status) return;
  // A servo that stopped itself (overload, overheating, ...) keeps its torque off until it is restarted.
  const Answer hardware =
      Transact(port, parser, clock_, id_, EncodeRead(id_, address::kHardwareErrorStatus, 1), 1, kAnswerS);
  if (!hardware.status) throw std::runtime_error("no answer to a read of the hardware error status");
  {
    std::lock_guard lock(mutex_);
    status_.model_number = pong.status->parameters[0] | pong.status->parameters[1] << 8;
    status_.hardware_error = hardware.status->parameters[0];
  }
  const auto reboot = [&](int error) {
    port.Write(EncodeReboot(id_));
    {
      std::lock_guard lock(mutex_);
      ++status_.reboots;
    }
    throw std::runtime_error(fmt::format("hardware error status {:#04x}: restarted the servo", error));
  };
  if (hardware.status->parameters[0] != 0) reboot(hardware.status->parameters[0]);
  // Set up: how fast it turns, then the torque on; each write must be answered.
  const auto velocity =
      static_cast<std::int32_t>(std::lround(options_.max_speed_dps * kToRad / x_series::kRpsPerVelocityUnit));
  const auto acceleration =
      static_cast<std::int32_t>(std::lround(options_.max_accel_dps2 * kToRad / x_series::kRps2PerAccelerationUnit));
  for (const auto& write :
       {WriteInt32(id_, address::kProfileAcceleration, std::max(1, acceleration)),
        WriteInt32(id_, address::kProfileVelocity, std::max(1, velocity)), WriteByte(id_, address::kTorqueEnable, 1)}) {
    const Answer answer = Transact(port, parser, clock_, id_, write, 0, kAnswerS);
    if (!answer.status) {
      std::lock_guard lock(mutex_);
      ++status_.device_errors;
      throw std::runtime_error(fmt::format("the servo refused its set-up (error byte {:#04x})", answer.error));
    }
  }
  last_reading_ns_ = clock_.Now();
  goal_written_ns_.reset();
  const std::vector<std::uint8_t> read_state = EncodeRead(id_, x_series::kStateFirst, x_series::kStateLength);
  const std::vector<std::uint8_t> read_hardware = EncodeRead(id_, address::kHardwareErrorStatus, 1);
  std::vector<StatusPacket> got;
  TimeNs next_read_ns = clock_.Now();
  bool alert_asked = false;
  Stream(
      port, stop, [&] { return std::max(1e-3, ToSeconds(next_read_ns - clock_.Now())); },
      [&](std::span<const std::uint8_t> bytes, bool) {
        const TimeNs now = clock_.Now();
        got.clear();
        parser.Push(bytes, got);
        for (const StatusPacket& status : got) {
          if (status.id != id_) continue;
          if ((status.error & ~kAlertBit) != 0) {
            std::lock_guard lock(mutex_);
            ++status_.device_errors;
            continue;
          }
          if (status.parameters.size() == 1) {  // the hardware error status, asked after an alert
            {
              std::lock_guard lock(mutex_);
              status_.hardware_error = status.parameters[0];
            }
            if (status.parameters[0] != 0) reboot(status.parameters[0]);
            alert_asked = false;
          }
          if ((status.error & kAlertBit) != 0 && !alert_asked) {
            port.Write(read_hardware);
            alert_asked = true;
          }
          if (status.parameters.size() == x_series::kStateLength) Take(status.parameters, now);
        }
        {
          std::lock_guard lock(mutex_);
          status_.dropped_packets = parser.dropped();
        }
        const double quiet_s = ToSeconds(now - last_reading_ns_);
        if (quiet_s > options_.silence_s) {
          SetState(LinkState::kSilent, fmt::format("no position for {:.1f} s: starting anew", options_.silence_s));
          return false;
        }
        if (quiet_s > options_.stale_s) {
          SetState(LinkState::kStale, fmt::format("no position for {:.0f} ms", options_.stale_s * 1e3));
        }
        if (const auto goal = GoalDue(now)) port.Write(*goal);
        if (Due(next_read_ns, now, options_.poll_period_s)) port.Write(read_state);
        return true;
      });
}

void DynamixelPanServo::Take(std::span<const std::uint8_t> state, TimeNs now) {
  const std::size_t velocity_at = x_series::address::kPresentVelocity - x_series::kStateFirst;
  const std::size_t position_at = x_series::address::kPresentPosition - x_series::kStateFirst;
  PanReading reading;
  reading.stamp_ns = now;
  reading.pan_rad = ToPan(ReadInt32(state, position_at));
  reading.velocity_rps =
      (options_.reversed ? -1.0 : 1.0) * ReadInt32(state, velocity_at) * x_series::kRpsPerVelocityUnit;
  last_reading_ns_ = now;
  ReadingHandler handler;
  {
    std::lock_guard lock(mutex_);
    ++status_.reads;
    status_.pan_rad = reading.pan_rad;
    handler = handler_;
  }
  SetState(LinkState::kRunning);
  if (handler) handler(reading);
}

std::optional<std::vector<std::uint8_t>> DynamixelPanServo::GoalDue(TimeNs now) {
  double target = 0.0;
  {
    std::lock_guard lock(mutex_);
    target = target_rad_;
  }
  const std::int32_t goal = ToPosition(target);
  if (goal == goal_written_ && goal_written_ns_ && ToSeconds(now - *goal_written_ns_) < options_.goal_refresh_s) {
    return std::nullopt;
  }
  goal_written_ = goal;
  goal_written_ns_ = now;
  return WriteInt32(id_, x_series::address::kGoalPosition, goal);
}

}  // namespace corridor::drivers::dynamixel
