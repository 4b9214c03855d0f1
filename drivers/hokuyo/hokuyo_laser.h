// A Hokuyo scanner (URG-04LX, UTM-30LX on USB serial; UST-10LX/20LX on TCP) through SCIP 2.0 (scip_protocol.h): the
// driver's thread opens the port (or connects), stops any stream under way, switches an older URG to SCIP 2.0, reads
// the device's parameters (range limits, steps, its front, scan rate), and starts the scans' stream (MD, every step,
// 3-character ranges); the stream's passes (on that thread, or the daemon's control loop pumping it) hand each on,
// stamped when it was taken (a pump's: up to a control tick after its last byte), as a LaserScan counter-clockwise from
// the front (REP-103: the device's steps already turn that way), ranges below the device's minimum (its error codes) or
// outside the configured limits as +infinity. A port that fails or goes away is reopened every reconnect_s; a device
// that sends no scan for silence_s is restarted. What it is doing is in status().
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "drivers/hokuyo/hokuyo_options.h"
#include "drivers/hokuyo/scip_protocol.h"
#include "drivers/laser2d.h"
#include "drivers/serial/byte_stream.h"
#include "drivers/serial/linked_device.h"

namespace corridor::drivers::hokuyo {

struct HokuyoStatus : LinkStatus {
  std::uint64_t scans = 0;               // scans handed on
  std::uint64_t dropped_answers = 0;     // answers whose check characters failed, or cut short
  std::optional<Parameters> parameters;  // the device's, once read
};

class HokuyoLaser final : public Laser2D, public LinkedDevice<HokuyoStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the scans and must outlive it.
  // Throws std::invalid_argument for options that cannot work.
  HokuyoLaser(const HokuyoOptions& options, const Clock& clock);
  ~HokuyoLaser() override;  // stops the stream and the laser, joins the thread

  nav::Pose2 base_T_laser() const override { return options_.base_T_laser; }
  double height_m() const override { return options_.height_m; }
  void SetScanHandler(ScanHandler handler) override;

 private:
  void Run(std::stop_token stop);
  // One session on an open stream: set-up, then scans until the stream fails, goes silent, or `stop`.
  void Session(ByteStream& stream, std::stop_token stop);
  // Sends `command` and waits answer_s for its answer (the one whose echo begins with it); none if it did not come.
  std::optional<Response> Ask(ByteStream& stream, ResponseReader& reader, const std::string& command);
  LaserScan ToScan(const Parameters& p, const ScanData& data, TimeNs stamp_ns) const;

  HokuyoOptions options_;
  const Clock& clock_;
  ScanHandler handler_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::hokuyo
