// A Kobuki (the base of a TurtleBot 2) on a serial port, through its protocol (kobuki_protocol.h): the Kobuki streams
// its sensors every 20 ms without being asked; the driver's thread turns the wheels' encoder counts into odometry and
// answers each report with a Base Control, the commanded velocity ramped to the acceleration limits. The wheels stop
// when commands stop arriving for command_timeout_s, while a cliff or a dropped wheel is reported, and while the
// stream is stale (stale_s without a report: the Kobuki keeps its last command otherwise). A port that fails
// (unplugged) or a stream silent for silence_s is opened anew every reconnect_s.
#pragma once

#include <mutex>
#include <string>
#include <thread>

#include "drivers/battery.h"
#include "drivers/diff_drive_base.h"
#include "drivers/kobuki/kobuki_options.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/serial/link_state.h"
#include "drivers/serial/serial_port.h"
#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::kobuki {

struct KobukiStatus : LinkStatus {
  std::uint64_t packets = 0;          // feedback packets with sensor data decoded
  std::uint64_t dropped_packets = 0;  // bad checksums and packets that did not add up
  bool cliff = false;
  bool wheel_drop = false;
};

class KobukiBase final : public DiffDriveBase, public Battery, public DeviceLink {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work (no port, non-positive timeouts or geometry).
  KobukiBase(const KobukiOptions& options, const Clock& clock);
  ~KobukiBase() override;  // stops the wheels, joins the thread

  BaseLimits limits() const override;
  void SetVelocity(const nav::Twist2& command) override;
  void SetOdometryHandler(OdometryHandler handler) override;
  void SetBatteryHandler(BatteryHandler handler) override;
  KobukiStatus status() const;
  LinkStatus link() const override { return status(); }
  void SetLinkHandler(LinkHandler handler) override;

 private:
  void Run(std::stop_token stop);
  // One session on an open port: reports until the port fails, goes silent, or `stop`.
  void Drive(SerialPort& port, std::stop_token stop);
  // The report's odometry and battery handed on, and the wheels' command for it.
  void Take(SerialPort& port, const SensorData& sensors);
  void SetState(LinkState state, std::string error = {});

  KobukiOptions options_;
  const Clock& clock_;
  mutable std::mutex mutex_;  // guards the command, the handlers and status_
  nav::Twist2 command_;
  TimeNs command_ns_ = 0;
  OdometryHandler odometry_handler_;
  BatteryHandler battery_handler_;
  LinkHandler link_handler_;
  KobukiStatus status_;
  // The driver's thread only.
  EncoderOdometry odometry_;
  TimeNs last_report_ns_ = 0;
  TimeNs last_battery_ns_ = 0;
  nav::Twist2 driven_;  // the ramped command sent last
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::kobuki
