// A TurtleBot 3's laser, LDS-01 or LDS-02 (lds_protocol.h), on a serial port: the driver's thread opens the port,
// starts an LDS-01 (the LDS-02 sends from power-up), and hands each revolution to the scan handler. A port that fails
// or goes away (the device unplugged) is reopened every reconnect_s, and one that sends no packet for silence_s too
// (rotating_laser.h). What it is doing is in status().
#pragma once

#include <cstdint>
#include <thread>

#include "drivers/lds/lds_options.h"
#include "drivers/rotating_laser.h"

namespace corridor::drivers::lds {

struct LdsStatus : LinkStatus {
  std::uint64_t scans = 0;          // revolutions handed on
  std::uint64_t packets = 0;        // packets taken
  std::uint64_t skipped_bytes = 0;  // noise, and packets that failed their checks, skipped
  double speed_deg_s = 0.0;         // an LDS-02's rotation speed as it reports it
};

class LdsLaser final : public RotatingLaser<LdsStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the scans (when a revolution's last byte arrived) and must outlive it.
  // Throws std::invalid_argument for options that cannot work.
  LdsLaser(const LdsOptions& options, const Clock& clock);
  ~LdsLaser() override;  // stops an LDS-01, joins the thread

 private:
  // One session on an open port: revolutions until the port fails, goes silent, or `stop`.
  void Scan(SerialPort& port, std::stop_token stop);

  LdsOptions options_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::lds
