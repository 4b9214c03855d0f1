// A TurtleBot 3's OpenCR board for tests, on a pseudo-terminal: a DYNAMIXEL Protocol 2.0 device 200 as ROBOTIS's
// e-Manual documents the protocol (framing, byte stuffing, CRC-16/0x8005; Ping, Read, Write; a status packet for each,
// with the error byte set for a bad CRC, an unknown instruction or an address out of the table) and the board's
// TurtleBot 3 control table (buttons, bumpers, battery, the wheels' velocities and positions, torque, the velocity
// command), written from those documents apart from the driver's codec. With torque on, the wheels turn at the
// commanded velocity at once; their positions count 4096 a turn of a 66 mm wheel, 160 mm apart (a Burger), as int32
// starting near their wrap. Faults: noise, an answer with a bad CRC, a slow board, silence, unplugging and plugging
// back in under the same path.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

class OpenCrEmulator {
 public:
  explicit OpenCrEmulator(std::filesystem::path link);
  ~OpenCrEmulator();
  OpenCrEmulator(const OpenCrEmulator&) = delete;
  OpenCrEmulator& operator=(const OpenCrEmulator&) = delete;

  std::pair<double, double> wheels_mps() const;  // left, right, as driven
  bool torque() const;
  int heartbeats() const;  // writes to the heartbeat
  int crc_errors() const;  // instruction packets refused for their CRC
  void SetBumper(bool pressed);
  void SetBattery(double volts, double percent);

  // Faults: bytes of noise before the next answer; the next answer's CRC wrong; every answer this much later; no
  // answers (and deaf) until Resume; the cable pulled, and plugged back in (the board restarted: torque off, still).
  void Noise(std::vector<std::uint8_t> bytes);
  void BadCrc();
  void Slow(double delay_s);
  void Silence();
  void Resume();
  void Unplug();
  void Replug();

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(std::uint8_t instruction, const std::vector<std::uint8_t>& parameters, double now_s);
  void Answer(std::uint8_t error, const std::vector<std::uint8_t>& parameters, double now_s);
  std::int32_t Int32At(std::size_t address) const;
  void SetInt32(std::size_t address, std::int32_t value);

  mutable std::mutex mutex_;
  PseudoTerminal terminal_;
  std::array<std::uint8_t, 256> table_{};
  std::vector<std::uint8_t> received_;
  std::deque<std::pair<double, std::vector<std::uint8_t>>> answers_;  // when due, what
  double left_mps_ = 0.0;
  double right_mps_ = 0.0;
  double left_ticks_ = 2147483647.0 - 2000.0;
  double right_ticks_ = 2147483647.0 - 2000.0;
  int heartbeats_ = 0;
  int crc_errors_ = 0;
  std::vector<std::uint8_t> noise_;
  bool bad_crc_ = false;
  double delay_s_ = 0.0;
  bool silent_ = false;
  double last_s_ = 0.0;
  std::jthread thread_;
};

}  // namespace corridor::testing
