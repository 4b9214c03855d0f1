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
  sent_oi_mode_ = -1;  // the first command is sent whatever it is
  last_frame_.reset();
  port.Write(EncodeStart());
  port.Write(EncodeSafe());
  port.Write(EncodeStream(StreamedPackets()));
  StreamParser parser;
  std::vector<SensorFrame> frames;
  const std::vector<std::uint8_t> stop_wheels = EncodeDriveDirect(0, 0);
  Stream(
      port, stop, [&] { return options_.stale_s; },
      [&](std::span<const std::uint8_t> bytes, bool) {
        frames.clear();
        parser.Push(bytes, frames);
        {
          std::lock_guard lock(mutex_);
          status_.dropped_frames = parser.dropped();
        }
        if (!frames.empty()) Take(frames);
        Command(port);
        return Watch(port, stop_wheels, "sensor frame");
      });
  port.Write(stop_wheels);
  port.Write(EncodePauseStream(false));
  port.Write(EncodeStop());
}

void Create2Base::Take(std::span<const SensorFrame> frames) {
  const TimeNs now = clock_.Now();
  Reported(now);
  bool bumped = false;
  for (const SensorFrame& frame : frames) {
    if (frame.has_encoders) odometry_.Update(now, frame.left_counts, frame.right_counts);
    bumped = bumped || frame.bump_left || frame.bump_right;
  }
  const SensorFrame& frame = frames.back();
  last_frame_ = frame;
  OdometryHandler odometry;
  BatteryHandler battery;
  {
    std::lock_guard lock(mutex_);
    status_.frames += frames.size();
    status_.oi_mode = frame.oi_mode;
    status_.cliff = frame.cliff;
    status_.wheel_drop = frame.wheel_drop_left || frame.wheel_drop_right;
    odometry = odometry_handler_;
    battery = BatteryDue(now);
  }
  SetState(LinkState::kRunning);
  if (odometry) odometry(WheelOdometry{now, odometry_.pose(), odometry_.velocity(), bumped, FloorMissing(frame)});
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

void Create2Base::Command(SerialPort& port) {
  const TimeNs now = clock_.Now();
  if (!last_frame_ || !Fresh(now)) return;  // Watch stops the wheels of a stale stream
  nav::Twist2 target;
  {
    std::lock_guard lock(mutex_);
    target = CommandAt(now);
  }
  const SensorFrame& frame = *last_frame_;
  const bool floor_missing = FloorMissing(frame);
  const nav::Twist2& driven = Drive(target, floor_missing, now);
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
}

bool Create2Base::FloorMissing(const SensorFrame& frame) {
  return frame.cliff || frame.wheel_drop_left || frame.wheel_drop_right;
}

}  // namespace corridor::drivers::create2
