// A TurtleBot 3 through its OpenCR board (opencr_table.h, DYNAMIXEL Protocol 2.0): the driver's thread pings the board
// and turns the wheels' torque on; then the stream's passes (on that thread, or the daemon's control loop pumping it)
// every poll_period_s read the board's state in one Read (buttons, bumpers, battery, the wheels' velocities and
// positions), turn the positions into odometry, and write the commanded velocity (ramped to the acceleration limits) as
// the board's velocity command, with a heartbeat every heartbeat_period_s. The wheels stop when commands stop arriving
// for command_timeout_s and while the state is stale. A port that fails or a board silent for silence_s is opened anew
// every reconnect_s. What it shares with the other bases: drivers/wheels/serial_base.h.
#pragma once

#include <cstdint>
#include <optional>

#include "drivers/dynamixel/dynamixel_protocol.h"
#include "drivers/turtlebot3/turtlebot3_options.h"
#include "drivers/wheels/serial_base.h"

namespace corridor::drivers::turtlebot3 {

struct TurtleBot3Status : LinkStatus {
  std::uint64_t reads = 0;            // state reads answered
  std::uint64_t dropped_packets = 0;  // status packets with a bad CRC or that did not add up
  std::uint64_t device_errors = 0;    // status packets whose error byte said the board refused
  int model_number = -1;              // the board's, from its answer to the ping
  bool bumper = false;
};

class TurtleBot3Base final : public SerialBase<TurtleBot3Options, TurtleBot3Status> {
 public:
  // Starts the driver's thread; `clock` stamps the odometry and must outlive the driver. Throws std::invalid_argument
  // for options that cannot work (no port, non-positive timeouts, periods or wheel geometry).
  TurtleBot3Base(const TurtleBot3Options& options, const Clock& clock);
  ~TurtleBot3Base() override;  // stops the wheels, joins the thread

 private:
  void Session(SerialPort& port, std::stop_token stop) override;
  // Sends `request` and waits up to timeout_s for the board's status with `parameters` bytes; none when it did not
  // come or the board refused.
  std::optional<dynamixel::StatusPacket> Transact(SerialPort& port, dynamixel::StatusParser& parser,
                                                  const std::vector<std::uint8_t>& request, std::size_t parameters,
                                                  double timeout_s);
  // The state read: odometry, bumpers and battery handed on, and the wheels' command written.
  void Take(SerialPort& port, std::span<const std::uint8_t> state);

  // The session's only (its thread, or the stream's passes).
  TimeNs last_heartbeat_ns_ = 0;
  std::uint8_t heartbeat_ = 0;
};

}  // namespace corridor::drivers::turtlebot3
