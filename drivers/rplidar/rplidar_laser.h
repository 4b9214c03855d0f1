// A Slamtec RPLIDAR (A1, A2, A3, C1, S-series) on a serial port, in standard scan mode (rplidar_protocol.h): the
// driver's thread opens the port, starts the motor (the A1's through DTR, inverted by its USB adapter; a pseudo-
// terminal has no modem lines and refuses, which is not an error), checks the device's health (resetting it once on
// an error), starts the scan and hands each revolution to the scan handler. A port that fails or goes away (the
// device unplugged) is reopened every reconnect_s; a device that says nothing for silence_s is restarted, so that one
// plugged back in under the same path (udev's stable name) scans again by itself. What it is doing is in status().
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "drivers/laser2d.h"
#include "drivers/rplidar/rplidar_options.h"
#include "drivers/rplidar/rplidar_protocol.h"
#include "drivers/serial/linked_device.h"
#include "drivers/serial/serial_port.h"

namespace corridor::drivers::rplidar {

struct RplidarStatus : LinkStatus {
  std::uint64_t scans = 0;           // revolutions handed on
  std::uint64_t skipped_bytes = 0;   // noise and lost bytes skipped in the node stream
  std::optional<DeviceInfo> info;
};

class RplidarLaser final : public Laser2D, public LinkedDevice<RplidarStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the scans (when a revolution's last byte arrived) and must outlive it.
  RplidarLaser(const RplidarOptions& options, const Clock& clock);
  ~RplidarLaser() override;  // stops the scan and the motor, joins the thread

  nav::Pose2 base_T_laser() const override { return options_.base_T_laser; }
  double height_m() const override { return options_.height_m; }
  void SetScanHandler(ScanHandler handler) override;

 private:
  void Run(std::stop_token stop);
  // One session on an open port: handshake, then revolutions until the port fails, goes silent, or `stop`.
  void Scan(SerialPort& port, std::stop_token stop);

  RplidarOptions options_;
  const Clock& clock_;
  ScanHandler handler_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::rplidar
