// An iRobot Create 2 (or Roomba 600-900; the base of a TurtleBot 2e) on a serial port, through its Open Interface
// (open_interface.h): the driver's thread starts the OI in Safe mode, streams the sensors it needs (every 15 ms), turns
// the wheels' encoder counts into odometry, and drives the wheels with Drive Direct on every frame, ramped to the
// acceleration limits. The wheels stop when commands stop arriving for command_timeout_s, and while a cliff or a
// dropped wheel is reported (the robot's own Safe mode stops them too and falls back to Passive; the driver returns it
// to Safe once the floor is back). A port that fails (unplugged) is reopened every reconnect_s; a stream silent for
// silence_s is restarted.
#pragma once

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>

#include "drivers/battery.h"
#include "drivers/create2/create2_options.h"
#include "drivers/create2/open_interface.h"
#include "drivers/diff_drive_base.h"
#include "drivers/serial/link_state.h"
#include "drivers/serial/serial_port.h"
#include "drivers/wheels/encoder_odometry.h"

namespace corridor::drivers::create2 {

struct Create2Status : LinkStatus {
  std::uint64_t frames = 0;          // sensor frames decoded
  std::uint64_t dropped_frames = 0;  // bad checksums and frames that did not add up
  int oi_mode = 0;                   // 0 off, 1 passive, 2 safe, 3 full
  bool cliff = false;
  bool wheel_drop = false;
};

class Create2Base final : public DiffDriveBase, public Battery, public DeviceLink {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver.
  Create2Base(const Create2Options& options, const Clock& clock);
  ~Create2Base() override;  // stops the wheels and the OI, joins the thread

  BaseLimits limits() const override;
  void SetVelocity(const nav::Twist2& command) override;
  void SetOdometryHandler(OdometryHandler handler) override;
  void SetBatteryHandler(BatteryHandler handler) override;
  Create2Status status() const;
  LinkStatus link() const override { return status(); }
  void SetLinkHandler(LinkHandler handler) override;

 private:
  void Run(std::stop_token stop);
  // One session on an open port: the OI started and streaming, frames until the port fails, goes silent, or `stop`.
  void Drive(SerialPort& port, std::stop_token stop);
  // The frame's odometry and battery handed on, and the wheels' command for it.
  void Take(SerialPort& port, const SensorFrame& frame);
  void SetState(LinkState state, std::string error = {});

  Create2Options options_;
  const Clock& clock_;
  mutable std::mutex mutex_;  // guards the command, the handlers and status_
  nav::Twist2 command_;
  TimeNs command_ns_ = 0;
  OdometryHandler odometry_handler_;
  BatteryHandler battery_handler_;
  LinkHandler link_handler_;
  Create2Status status_;
  // The driver's thread only.
  EncoderOdometry odometry_;
  TimeNs last_frame_ns_ = 0;
  TimeNs last_battery_ns_ = 0;
  TimeNs last_safe_ns_ = 0;
  nav::Twist2 driven_;  // the ramped command sent last
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::create2
