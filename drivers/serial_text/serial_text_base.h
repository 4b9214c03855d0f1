// A home-made differential base whose microcontroller speaks the serial text protocol (serial_text_protocol.h,
// ROSArduinoBridge's commands): the driver's thread waits for the board to answer; then the stream's passes (on that
// thread, or the daemon's control loop pumping it) ask for the encoders' counts every poll_period_s, turn them into
// odometry, and answer each reply with the wheels' speeds, the commanded velocity ramped to the acceleration limits.
// The text has no checksum: a reply that lost or changed a digit would move the robot's pose by metres, so counts
// that moved further than the wheels can turn are dropped, and three such replies in a row are taken as the board
// having restarted counting. The wheels stop when commands stop arriving for command_timeout_s and while the replies
// are stale (the board keeps its last speeds for 2 s otherwise). The protocol has no bumper, cliff or battery. A port
// that fails or a board silent for silence_s is opened anew every reconnect_s (the board restarts, and is given boot_s
// to answer). What it shares with the other bases: drivers/wheels/serial_base.h.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "drivers/serial_text/serial_text_options.h"
#include "drivers/serial_text/serial_text_protocol.h"
#include "drivers/wheels/serial_base.h"

namespace corridor::drivers::serial_text {

struct SerialTextStatus : LinkStatus {
  std::uint64_t replies = 0;      // encoder replies taken
  std::uint64_t bad_lines = 0;    // lines that were neither counts nor OK (garbage, Invalid Command), or too long
  std::uint64_t implausible = 0;  // counts dropped for moving further than the wheels can
  std::uint64_t restarts = 0;     // times the board was found counting anew
};

class SerialTextBase final : public SerialBase<SerialTextOptions, SerialTextStatus> {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work (no port, no wheel geometry, non-positive timeouts or rates).
  SerialTextBase(const SerialTextOptions& options, const Clock& clock);
  ~SerialTextBase() override;  // stops the wheels, joins the thread

 private:
  void Session(SerialPort& port, std::stop_token stop) override;
  // Asks for the counts until the board answers (it may be restarting): throws after boot_s without an answer.
  void AwaitBoard(SerialPort& port, LineSplitter& lines, std::stop_token stop);
  // What came: counts taken, the rest counted as bad.
  void Handle(SerialPort& port, LineSplitter& lines, std::span<const std::uint8_t> bytes);
  void Take(SerialPort& port, const EncoderCounts& counts);
  // Asks for the counts ('e'), noting when.
  void Ask(SerialPort& port);
  // When the ask a reply answers was sent (replies come in the order of the asks; now when none is outstanding).
  TimeNs Answered(TimeNs now);
  double CountsPerMetre() const;
  // Counts a wheel at `mps` turns in one PID frame.
  int CountsPerFrame(double mps) const;

  // The session's only (its thread, or the stream's passes).
  std::optional<EncoderCounts> last_counts_;
  // When the ask that the last believed counts answered was sent: the board measured them no earlier, so the wheels
  // turned for at most the time from then to a reply's arrival, however late the replies are taken.
  TimeNs last_counts_asked_ns_ = 0;
  std::deque<TimeNs> asks_;  // when each ask not yet answered was sent, oldest first
  int implausible_run_ = 0;
};

}  // namespace corridor::drivers::serial_text
