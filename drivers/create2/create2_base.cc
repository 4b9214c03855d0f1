#include "drivers/create2/create2_base.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace corridor::drivers::create2 {
namespace {

// Safe mode is asked for again at most this often while the robot sits in Passive (after a cliff or a dropped
// wheel): the OI takes a moment to change modes.
constexpr double kSafeRetryS = 0.5;
// The wheels' command is sent when it changes, and again this often: the OI keeps the last one (it has no timeout of
// its own), and a command lost on the line is put right within this time.
constexpr double kDriveRefreshS = 0.25;

}  // namespace

Create2Base::Create2Base(const Create2Options& options, const Clock& clock) : SerialBase("create2", options, clock) {
  Start();
}

Create2Base::~Create2Base() { StopThread(); }

void Create2Base::Session(SerialPort& port, std::stop_token stop) {
  Begin();
  sent_oi_mode_ = -1;  // the first frame's command is sent whatever it is
  port.Write(EncodeStart());
  port.Write(EncodeSafe());
  port.Write(EncodeStream(StreamedPackets()));
  StreamParser parser;
  std::vector<SensorFrame> frames;
  std::array<std::uint8_t, 256> buffer{};
  const std::vector<std::uint8_t> stop_wheels = EncodeDriveDirect(0, 0);
  while (!stop.stop_requested()) {
    const std::size_t n = port.Read(buffer, options_.stale_s);
    frames.clear();
    parser.Push(std::span<const std::uint8_t>(buffer.data(), n), frames);
    {
      std::lock_guard lock(mutex_);
      status_.dropped_frames = parser.dropped();
    }
    for (const SensorFrame& frame : frames) Take(port, frame);
    if (!Watch(port, stop_wheels, "sensor frame")) return;
  }
  port.Write(stop_wheels);
  port.Write(EncodePauseStream(false));
  port.Write(EncodeStop());
}

void Create2Base::Take(SerialPort& port, const SensorFrame& frame) {
  const TimeNs now = clock_.Now();
  const double dt = Reported(now);
  if (frame.has_encoders) odometry_.Update(now, frame.left_counts, frame.right_counts);
  // The wheels' command: zero when commands stopped coming or the floor is not there.
  nav::Twist2 target;
  OdometryHandler odometry;
  BatteryHandler battery;
  {
    std::lock_guard lock(mutex_);
    target = CommandAt(now);
    ++status_.frames;
    status_.oi_mode = frame.oi_mode;
    status_.cliff = frame.cliff;
    status_.wheel_drop = frame.wheel_drop_left || frame.wheel_drop_right;
    odometry = odometry_handler_;
    battery = BatteryDue(now);
  }
  SetState(LinkState::kRunning);
  const bool floor_missing = frame.cliff || frame.wheel_drop_left || frame.wheel_drop_right;
  const nav::Twist2& driven = Drive(target, floor_missing, dt);
  const double half_track = 0.5 * options_.wheels.track_m;
  const auto mmps = [](double mps) { return static_cast<int>(std::lround(mps * 1000.0)); };
  const std::array<int, 2> wheels{mmps(driven.linear_mps - half_track * driven.angular_rps),
                                  mmps(driven.linear_mps + half_track * driven.angular_rps)};
  if (wheels != sent_mmps_ || frame.oi_mode != sent_oi_mode_ || ToSeconds(now - sent_ns_) >= kDriveRefreshS) {
    port.Write(EncodeDriveDirect(wheels[0], wheels[1]));
    sent_mmps_ = wheels;
    sent_oi_mode_ = frame.oi_mode;
    sent_ns_ = now;
  }
  // Passive after a safety stop: Safe again once the floor is back.
  if (frame.oi_mode == 1 && !floor_missing && ToSeconds(now - last_safe_ns_) >= kSafeRetryS) {
    port.Write(EncodeSafe());
    last_safe_ns_ = now;
  }
  if (odometry) {
    odometry(
        WheelOdometry{now, odometry_.pose(), odometry_.velocity(), frame.bump_left || frame.bump_right, floor_missing});
  }
  if (battery) {
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
