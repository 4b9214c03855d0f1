// A camera's pan servo: an X-series DYNAMIXEL (x_series_table.h) over Protocol 2.0 on a serial line (a U2D2, or any
// half-duplex TTL/RS-485 adapter that turns the line around by itself). The driver's thread pings the servo, checks
// its hardware error status (a servo that reports one is restarted with a Reboot and set up anew), gives it the
// profile velocity and acceleration, turns its torque on and sends it to its goal; then the stream's passes, every
// poll_period_s, read the present velocity and position in one Read and hand them on as PanReadings, and write the goal
// when it changed (and every goal_refresh_s). A status packet with the alert bit makes the driver read the hardware
// error status, and one that is not 0 ends the session after a Reboot. Positions stale for stale_s make the link
// stale (the camera's frames go unused and the command gate stops the robot); silent for silence_s, the port is
// opened anew every reconnect_s.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <thread>

#include "drivers/clock.h"
#include "drivers/dynamixel/dynamixel_protocol.h"
#include "drivers/dynamixel/pan_servo_options.h"
#include "drivers/pan_servo.h"
#include "drivers/serial/linked_device.h"
#include "drivers/serial/serial_port.h"

namespace corridor::drivers::dynamixel {

struct PanServoStatus : LinkStatus {
  std::uint64_t reads = 0;            // position reads answered
  std::uint64_t dropped_packets = 0;  // status packets with a bad CRC or that did not add up
  std::uint64_t device_errors = 0;    // status packets whose error byte said the servo refused
  std::uint64_t reboots = 0;          // hardware errors cleared by a Reboot
  int model_number = -1;              // from its answer to the ping (XL430-W250: 1060)
  int hardware_error = 0;             // the last hardware error status read (0: none)
  double pan_rad = 0.0;               // the last position read
};

class DynamixelPanServo final : public PanServo, public LinkedDevice<PanServoStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the readings and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work (no port, an id outside 0-252, limits not around 0, non-positive periods).
  DynamixelPanServo(const PanServoOptions& options, const Clock& clock);
  ~DynamixelPanServo() override;

  PanLimits pan_limits() const override;
  Eigen::Vector2d axis_xy() const override { return {options_.axis_x_m, options_.axis_y_m}; }
  void SetTarget(double pan_rad) override;
  void SetReadingHandler(ReadingHandler handler) override;

  // Counts to the camera's angle and back, as the options' centre and direction say.
  double ToPan(std::int32_t position) const;
  std::int32_t ToPosition(double pan_rad) const;

 private:
  void Run(std::stop_token stop);
  void Session(SerialPort& port, std::stop_token stop);
  // A reading of the present velocity and position taken at `now`.
  void Take(std::span<const std::uint8_t> state, TimeNs now);
  // The goal's write when due (changed, or goal_refresh_s since the last), else none.
  std::optional<std::vector<std::uint8_t>> GoalDue(TimeNs now);

  const PanServoOptions options_;
  const Clock& clock_;
  const std::uint8_t id_;
  // Under mutex_:
  double target_rad_ = 0.0;
  ReadingHandler handler_;
  // The session's only (its thread, or the stream's passes):
  TimeNs last_reading_ns_ = 0;
  std::optional<TimeNs> goal_written_ns_;  // none: not yet this session
  std::int32_t goal_written_ = 0;
  std::jthread thread_;
};

}  // namespace corridor::drivers::dynamixel
