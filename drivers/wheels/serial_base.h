// What the native base drivers (Create 2, Kobuki, TurtleBot 3, serial text) share around their own protocol: options
// checked once, the velocity asked for (clamped to the limits, with when it came), the odometry, battery and link
// handlers and the driver's status under one mutex, the driver's thread running sessions on the serial port and
// reopening it when it fails (drivers/serial/linked_device.h, whose Stream runs a session's passes on the driver's
// thread or a pumping one), the watch for a stream gone quiet, the wheels' command ramped, and the odometry from the
// encoders. A driver supplies Session: one session on an open port, its protocol's commands and reports.
//
// `Options` has the bases' common keys (port, baud_rate, wheels, max_linear_mps, max_angular_rps,
// max_linear_accel_mps2, max_angular_accel_rps2, footprint_radius_m, command_timeout_s, stale_s, silence_s,
// reconnect_s, battery_period_s); `Status` extends LinkStatus.
#pragma once

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>

#include <spdlog/fmt/fmt.h>

#include "drivers/battery.h"
#include "drivers/diff_drive_base.h"
#include "drivers/serial/linked_device.h"
#include "drivers/serial/serial_port.h"
#include "drivers/wheels/command_ramp.h"
#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers {

template <typename Options, typename Status>
class SerialBase : public DiffDriveBase, public Battery, public LinkedDevice<Status> {
 public:
  ~SerialBase() override { StopThread(); }

  BaseLimits limits() const override {
    return {options_.max_linear_mps, options_.max_angular_rps, options_.max_linear_accel_mps2,
            options_.max_angular_accel_rps2, options_.footprint_radius_m};
  }
  void SetVelocity(const nav::Twist2& command) override {
    std::lock_guard lock(mutex_);
    command_ = {std::clamp(command.linear_mps, -options_.max_linear_mps, options_.max_linear_mps),
                std::clamp(command.angular_rps, -options_.max_angular_rps, options_.max_angular_rps)};
    command_ns_ = clock_.Now();
  }
  void SetOdometryHandler(OdometryHandler handler) override {
    std::lock_guard lock(mutex_);
    odometry_handler_ = std::move(handler);
  }
  void SetBatteryHandler(BatteryHandler handler) override {
    std::lock_guard lock(mutex_);
    battery_handler_ = std::move(handler);
  }

 protected:
  using LinkedDevice<Status>::mutex_;  // guards the command, the handlers and status_
  using LinkedDevice<Status>::status_;
  using LinkedDevice<Status>::SetState;

  // `device`: the driver's name in its errors and logs. Throws std::invalid_argument for options that cannot work (no
  // port, non-positive timeouts or wheel geometry, silence_s not longer than stale_s).
  SerialBase(std::string device, const Options& options, const Clock& clock)
      : LinkedDevice<Status>(device, options.port.string()),
        options_(Checked(device, options)),
        clock_(clock),
        odometry_(options_.wheels) {}

  // Starts the driver's thread: the subclass's constructor calls it last. Its destructor calls StopThread first.
  void Start() {
    thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
  }
  void StopThread() {
    thread_.request_stop();
    if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
  }

  // One session on an open port: until the port fails, the stream falls silent, or `stop`. Its streaming part goes
  // through Stream (linked_device.h), whose passes may run on a pumping thread.
  virtual void Session(SerialPort& port, std::stop_token stop) = 0;

  // After each pass: no report for stale_s and the link is stale (the wheels get `stop_wheels`: the robot keeps its
  // last command otherwise, for as long as it may still listen); for silence_s, false: the session ends.
  bool Watch(SerialPort& port, std::span<const std::uint8_t> stop_wheels, const char* report) {
    const double quiet_s = ToSeconds(clock_.Now() - last_report_ns_);
    if (quiet_s > options_.silence_s) {
      SetState(LinkState::kSilent, fmt::format("no {} for {:.1f} s: starting anew", report, options_.silence_s));
      return false;
    }
    if (quiet_s > options_.stale_s) {
      SetState(LinkState::kStale, fmt::format("no {} for {:.0f} ms", report, options_.stale_s * 1e3));
      port.Write(stop_wheels);
      driven_ = {};
    }
    return true;
  }
  // A report came at `now`.
  void Reported(TimeNs now) { last_report_ns_ = now; }
  // Whether the last report is at most stale_s old.
  bool Fresh(TimeNs now) const { return ToSeconds(now - last_report_ns_) <= options_.stale_s; }
  // With mutex_ held: the velocity asked for, zero once commands stopped coming for command_timeout_s.
  nav::Twist2 CommandAt(TimeNs now) const {
    return ToSeconds(now - command_ns_) <= options_.command_timeout_s ? command_ : nav::Twist2{};
  }
  // With mutex_ held: the battery handler when a report is due (every battery_period_s), else none.
  BatteryHandler BatteryDue(TimeNs now) {
    if (ToSeconds(now - last_battery_ns_) < options_.battery_period_s || !battery_handler_) return {};
    last_battery_ns_ = now;
    return battery_handler_;
  }
  // The wheels' command at `now`: `target` ramped to the acceleration limits since the command before (at least
  // 1 ms), or zero at once while the floor is missing.
  const nav::Twist2& Drive(const nav::Twist2& target, bool floor_missing, TimeNs now) {
    const double dt = std::max(1e-3, ToSeconds(now - driven_ns_));
    driven_ns_ = now;
    driven_ = floor_missing
                  ? nav::Twist2{}
                  : RampToward(driven_, target, options_.max_linear_accel_mps2, options_.max_angular_accel_rps2, dt);
    return driven_;
  }
  // A session begins: the device may have been power-cycled (its counts start anew) and its wheels are still.
  void Begin() {
    SetState(LinkState::kConnecting);
    odometry_.Restart();
    driven_ = {};
    last_report_ns_ = driven_ns_ = clock_.Now();
  }

  const Options options_;
  const Clock& clock_;
  OdometryHandler odometry_handler_;
  // The session's only (its thread, or the stream's passes).
  EncoderOdometry odometry_;

 private:
  static const Options& Checked(const std::string& device, const Options& o) {
    if (o.port.empty()) throw std::invalid_argument(device + ": no port given");
    if (!(o.command_timeout_s > 0.0) || !(o.stale_s > 0.0) || !(o.silence_s > o.stale_s) || !(o.reconnect_s > 0.0) ||
        !o.wheels.Valid()) {
      throw std::invalid_argument(device +
                                  ": timeouts and wheel geometry must be positive, and silence_s longer than stale_s");
    }
    return o;
  }
  void Run(std::stop_token stop) {
    this->RunSessions(stop, options_.reconnect_s, [&] {
      SerialPort port(options_.port, options_.baud_rate);
      Session(port, stop);
    });
  }

  nav::Twist2 command_;
  TimeNs command_ns_ = 0;
  BatteryHandler battery_handler_;
  TimeNs last_report_ns_ = 0;   // the stream's passes only
  TimeNs last_battery_ns_ = 0;  // under mutex_
  nav::Twist2 driven_;          // the ramped command sent last, and when; the stream's passes only
  TimeNs driven_ns_ = 0;
  std::jthread thread_;
};

}  // namespace corridor::drivers
