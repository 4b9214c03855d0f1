// A Kobuki (the base of a TurtleBot 2) on a serial port, through its protocol (kobuki_protocol.h): the Kobuki streams
// its sensors every 20 ms without being asked; the stream's passes (on the driver's thread, or the daemon's control
// loop pumping it) turn the wheels' encoder counts into odometry and answer each report with a Base Control, the
// commanded velocity ramped to the acceleration limits. The wheels stop when commands stop arriving for
// command_timeout_s, while a cliff or a dropped wheel is reported, and while the stream is stale (stale_s without a
// report: the Kobuki keeps its last command otherwise). A port that fails (unplugged) or a stream silent for silence_s
// is opened anew every reconnect_s. What it shares with the other bases: drivers/wheels/serial_base.h.
#pragma once

#include <cstdint>

#include "drivers/kobuki/kobuki_options.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/wheels/serial_base.h"

namespace corridor::drivers::kobuki {

struct KobukiStatus : LinkStatus {
  std::uint64_t packets = 0;          // feedback packets with sensor data decoded
  std::uint64_t dropped_packets = 0;  // bad checksums and packets that did not add up
  bool cliff = false;
  bool wheel_drop = false;
};

class KobukiBase final : public SerialBase<KobukiOptions, KobukiStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work (no port, non-positive timeouts or geometry, the battery's full not above empty).
  KobukiBase(const KobukiOptions& options, const Clock& clock);
  ~KobukiBase() override;  // stops the wheels, joins the thread

 private:
  void Session(SerialPort& port, std::stop_token stop) override;
  // The report's odometry and battery handed on, and the wheels' command for it.
  void Take(SerialPort& port, const SensorData& sensors);
};

}  // namespace corridor::drivers::kobuki
