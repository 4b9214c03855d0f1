#include "drivers/kobuki/kobuki_base.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

namespace corridor::drivers::kobuki {

KobukiBase::KobukiBase(const KobukiOptions& options, const Clock& clock) : SerialBase("kobuki", options, clock) {
  if (!(options.battery_full_v > options.battery_empty_v)) {
    throw std::invalid_argument("kobuki: battery_full_v must be above battery_empty_v");
  }
  Start();
}

KobukiBase::~KobukiBase() { StopThread(); }

void KobukiBase::Session(SerialPort& port, std::stop_token stop) {
  Begin();
  PacketParser parser;
  std::vector<FeedbackPacket> packets;
  const std::vector<std::uint8_t> stop_wheels = EncodeBaseControl({});
  Stream(
      port, stop, [&] { return options_.stale_s; },
      [&](std::span<const std::uint8_t> bytes, bool) {
        packets.clear();
        parser.Push(bytes, packets);
        {
          std::lock_guard lock(mutex_);
          status_.dropped_packets = parser.dropped();
        }
        for (const FeedbackPacket& packet : packets) {
          if (packet.sensors) Take(port, *packet.sensors);
        }
        return Watch(port, stop_wheels, "feedback");
      });
  port.Write(stop_wheels);
}

void KobukiBase::Take(SerialPort& port, const SensorData& sensors) {
  const TimeNs now = clock_.Now();
  Reported(now);
  odometry_.Update(now, sensors.left_counts, sensors.right_counts);
  const bool floor_missing = sensors.cliff || sensors.wheel_drop_left || sensors.wheel_drop_right;
  nav::Twist2 target;
  OdometryHandler odometry;
  BatteryHandler battery;
  {
    std::lock_guard lock(mutex_);
    target = CommandAt(now);
    ++status_.packets;
    status_.cliff = sensors.cliff;
    status_.wheel_drop = sensors.wheel_drop_left || sensors.wheel_drop_right;
    odometry = odometry_handler_;
    battery = BatteryDue(now);
  }
  SetState(LinkState::kRunning);
  port.Write(EncodeBaseControl(ToBaseControl(Drive(target, floor_missing, now), options_.wheels.track_m)));
  if (odometry) {
    odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(),
                           sensors.bump_left || sensors.bump_centre || sensors.bump_right, floor_missing});
  }
  if (battery) {
    BatteryState state;
    state.stamp_ns = now;
    state.charge = std::clamp(
        (sensors.battery_v - options_.battery_empty_v) / (options_.battery_full_v - options_.battery_empty_v), 0.0,
        1.0);
    state.voltage_v = sensors.battery_v;
    state.charging = Charging(sensors.charger);
    state.on_charger = OnDock(sensors.charger);
    battery(state);
  }
}

}  // namespace corridor::drivers::kobuki
