// A Slamtec RPLIDAR (A1, A2, A3, C1, S-series) on a serial port, in standard or express scan mode
// (rplidar_protocol.h): the driver's thread opens the port, starts the motor (the A1's through DTR, inverted by its
// USB adapter; a pseudo-terminal has no modem lines and refuses, which is not an error), checks the device's health
// (resetting it once on an error), starts the scan and hands each revolution to the scan handler. A port that fails
// or goes away (the device unplugged) is reopened every reconnect_s, and a device that sends no measurement for
// silence_s is started again (rotating_laser.h). What it is doing is in status().
#pragma once

#include <cstdint>
#include <optional>
#include <thread>

#include "drivers/rotating_laser.h"
#include "drivers/rplidar/rplidar_options.h"
#include "drivers/rplidar/rplidar_protocol.h"

namespace corridor::drivers::rplidar {

struct RplidarStatus : LinkStatus {
  std::uint64_t scans = 0;          // revolutions handed on
  std::uint64_t skipped_bytes = 0;  // noise, lost bytes and capsules that failed their checksum, skipped
  std::optional<DeviceInfo> info;
};

class RplidarLaser final : public RotatingLaser<RplidarStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the scans (when a revolution's last byte arrived) and must outlive it.
  // Throws std::invalid_argument for options that cannot work.
  RplidarLaser(const RplidarOptions& options, const Clock& clock);
  ~RplidarLaser() override;  // stops the scan and the motor, joins the thread

 private:
  // One session on an open port: handshake, then revolutions until the port fails, goes silent, or `stop`.
  void Scan(SerialPort& port, std::stop_token stop);

  RplidarOptions options_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::rplidar
