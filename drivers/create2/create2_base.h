// An iRobot Create 2 (or Roomba 600-900; the base of a TurtleBot 2e) on a serial port, through its Open Interface
// (open_interface.h): the driver's thread starts the OI in Safe mode and streams the sensors it needs (every 15 ms);
// the stream's passes (on that thread, or the daemon's control loop pumping it) turn the wheels' encoder counts into
// odometry, and drive the wheels with Drive Direct, ramped to the acceleration limits (sent when the speeds change,
// and at least every 0.25 s). The wheels stop when commands stop arriving for
// command_timeout_s, and while a cliff or a dropped wheel is reported (the robot's own Safe mode stops them too and
// falls back to Passive; the driver returns it to Safe once the floor is back). A port that fails (unplugged) is
// reopened every reconnect_s; a stream silent for silence_s is restarted. What it shares with the other bases:
// drivers/wheels/serial_base.h.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "drivers/create2/create2_options.h"
#include "drivers/create2/open_interface.h"
#include "drivers/wheels/serial_base.h"

namespace corridor::drivers::create2 {

struct Create2Status : LinkStatus {
  std::uint64_t frames = 0;          // sensor frames decoded
  std::uint64_t dropped_frames = 0;  // bad checksums and frames that did not add up
  int oi_mode = 0;                   // 0 off, 1 passive, 2 safe, 3 full
  bool cliff = false;
  bool wheel_drop = false;
};

class Create2Base final : public SerialBase<Create2Options, Create2Status> {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work.
  Create2Base(const Create2Options& options, const Clock& clock);
  ~Create2Base() override;  // stops the wheels and the OI, joins the thread

 private:
  void Session(SerialPort& port, std::stop_token stop) override;
  // A pass's frames (at least one) taken: one odometry report handed on (the pose after the last, bumped if any
  // was), and the battery when due.
  void Take(std::span<const SensorFrame> frames);
  // The wheels' command for the last frame and the velocity asked for now, sent when it changed (and Safe mode asked
  // for again after a safety stop): after every pass, so that a new command goes out with the pass after it.
  void Command(SerialPort& port);
  static bool FloorMissing(const SensorFrame& frame);

  // The session's only (its thread, or the stream's passes):
  std::optional<SensorFrame> last_frame_;
  TimeNs last_safe_ns_ = 0;
  std::array<int, 2> sent_mmps_{};  // the last Drive Direct sent (left, right), its time, and the OI mode then
  TimeNs sent_ns_ = 0;
  int sent_oi_mode_ = -1;
};

}  // namespace corridor::drivers::create2
