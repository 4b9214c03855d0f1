#include "drivers/turtlebot3/turtlebot3_base.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "drivers/dynamixel/dynamixel_link.h"
#include "drivers/turtlebot3/opencr_table.h"

namespace corridor::drivers::turtlebot3 {
namespace {

using dynamixel::StatusPacket;
using dynamixel::StatusParser;

// While the board is awaited, it is pinged this often.
constexpr double kPingPeriodS = 0.2;

std::vector<std::uint8_t> VelocityCommand(const nav::Twist2& twist) {
  const auto hundredths = [](double value) { return static_cast<std::int32_t>(std::lround(value * 100.0)); };
  std::vector<std::uint8_t> data;
  dynamixel::AppendInt32(data, hundredths(twist.linear_mps));
  for (int i = 0; i < 4; ++i) dynamixel::AppendInt32(data, 0);  // linear y, z; angular x, y
  dynamixel::AppendInt32(data, hundredths(twist.angular_rps));
  return dynamixel::EncodeWrite(kOpenCrId, address::kCmdVelocityLinearX, data);
}

}  // namespace

TurtleBot3Base::TurtleBot3Base(const TurtleBot3Options& options, const Clock& clock)
    : SerialBase("turtlebot3", options, clock) {
  if (!(options.poll_period_s > 0.0) || !(options.connect_s > 0.0) || !(options.heartbeat_period_s > 0.0)) {
    throw std::invalid_argument("turtlebot3: poll_period_s, connect_s and heartbeat_period_s must be positive");
  }
  Start();
}

TurtleBot3Base::~TurtleBot3Base() { StopThread(); }

void TurtleBot3Base::Session(SerialPort& port, std::stop_token stop) {
  Begin();
  StatusParser parser;
  // The board, found by a ping (its answer: the model number and the firmware's version).
  std::optional<StatusPacket> pong;
  for (const TimeNs give_up = clock_.Now() + FromSeconds(options_.connect_s); !pong && !stop.stop_requested();) {
    if (clock_.Now() >= give_up) {
      throw std::runtime_error(fmt::format("no answer to a ping of device {} within {:.1f} s (an OpenCR at {} baud?)",
                                           kOpenCrId, options_.connect_s, options_.baud_rate));
    }
    pong = Transact(port, parser, dynamixel::EncodePing(kOpenCrId), 3, kPingPeriodS);
  }
  if (!pong) return;
  {
    std::lock_guard lock(mutex_);
    status_.model_number = pong->parameters[0] | pong->parameters[1] << 8;
  }
  const std::array<std::uint8_t, 1> torque_on{1};
  port.Write(dynamixel::EncodeWrite(kOpenCrId, address::kMotorTorqueEnable, torque_on));
  Reported(clock_.Now());  // the state is watched from here
  const std::vector<std::uint8_t> stop_wheels = VelocityCommand({});
  const std::vector<std::uint8_t> read_state = dynamixel::EncodeRead(kOpenCrId, kStateFirst, kStateLength);
  std::vector<StatusPacket> got;
  TimeNs next_read_ns = clock_.Now();
  // Each pass takes the state that came (the answers to the writes are passed over), and asks for it again when due.
  Stream(
      port, stop, [&] { return std::max(1e-3, ToSeconds(next_read_ns - clock_.Now())); },
      [&](std::span<const std::uint8_t> bytes, bool) {
        got.clear();
        parser.Push(bytes, got);
        for (const StatusPacket& status : got) {
          if (status.id != kOpenCrId || status.parameters.size() != kStateLength) continue;  // a write's answer
          if ((status.error & ~dynamixel::kAlertBit) != 0) {
            std::lock_guard lock(mutex_);
            ++status_.device_errors;
            continue;
          }
          Take(port, status.parameters);
        }
        {
          std::lock_guard lock(mutex_);
          status_.dropped_packets = parser.dropped();
        }
        if (Due(next_read_ns, clock_.Now(), options_.poll_period_s)) port.Write(read_state);
        return Watch(port, stop_wheels, "state");
      });
  port.Write(stop_wheels);
}

std::optional<StatusPacket> TurtleBot3Base::Transact(SerialPort& port, StatusParser& parser,
                                                     const std::vector<std::uint8_t>& request, std::size_t parameters,
                                                     double timeout_s) {
  dynamixel::Answer answer = dynamixel::Transact(port, parser, clock_, kOpenCrId, request, parameters, timeout_s);
  if (answer.refused) {
    std::lock_guard lock(mutex_);
    ++status_.device_errors;
  }
  return std::move(answer.status);
}

void TurtleBot3Base::Take(SerialPort& port, std::span<const std::uint8_t> state) {
  const auto at = [](std::uint16_t address) { return static_cast<std::size_t>(address - kStateFirst); };
  const TimeNs now = clock_.Now();
  Reported(now);
  // The positions' low 16 bits: the odometry's wrap-around arithmetic holds for any count width.
  odometry_.Update(now, static_cast<std::uint16_t>(dynamixel::ReadInt32(state, at(address::kPresentPositionLeft))),
                   static_cast<std::uint16_t>(dynamixel::ReadInt32(state, at(address::kPresentPositionRight))));
  const bool bumper = state[at(address::kBumper1)] != 0 || state[at(address::kBumper2)] != 0;
  nav::Twist2 target;
  OdometryHandler odometry;
  BatteryHandler battery;
  {
    std::lock_guard lock(mutex_);
    target = CommandAt(now);
    ++status_.reads;
    status_.bumper = bumper;
    odometry = odometry_handler_;
    battery = BatteryDue(now);
  }
  SetState(LinkState::kRunning);
  port.Write(VelocityCommand(Drive(target, false, now)));
  if (ToSeconds(now - last_heartbeat_ns_) >= options_.heartbeat_period_s) {
    const std::array<std::uint8_t, 1> beat{++heartbeat_};
    port.Write(dynamixel::EncodeWrite(kOpenCrId, address::kHeartbeat, beat));
    last_heartbeat_ns_ = now;
  }
  if (odometry) odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(), bumper, false});
  if (battery) {
    BatteryState b;
    b.stamp_ns = now;
    b.voltage_v = 0.01 * dynamixel::ReadInt32(state, at(address::kBatteryVoltage));
    b.charge = std::clamp(1e-4 * dynamixel::ReadInt32(state, at(address::kBatteryPercentage)), 0.0, 1.0);
    battery(b);
  }
}

}  // namespace corridor::drivers::turtlebot3
