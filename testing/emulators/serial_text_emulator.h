// A home-made base's microcontroller for tests, on a pseudo-terminal: the board's side of the ROSArduinoBridge serial
// text protocol as its README documents it (commands ended by CR, answers by CR LF; `e` the encoders' counts, `m L R`
// the wheels' speeds in counts per PID frame at 30 frames a second, `r` the counts to zero, `b` the baud rate, anything
// else "Invalid Command"; the wheels stopped 2 s after the last `m`), written from that document apart from the
// driver's codec. The wheels turn at the speeds asked for at once (a perfect PID); the signed 32-bit counts start near
// their wrap so that tests cross it. The board boots (deaf) for boot_s when it starts and when it is plugged back in,
// and then counts from zero. Faults: noise, a reply that loses a byte, replies lost, a slow board, silence, a restart
// without the port closing (the counts back to zero), unplugging and plugging back in under the same path.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

struct SerialTextGeometry {
  double wheel_diameter_m = 0.065;
  double track_m = 0.20;
  double counts_per_revolution = 1920.0;
};

class SerialTextEmulator {
 public:
  explicit SerialTextEmulator(std::filesystem::path link, SerialTextGeometry geometry = {}, double boot_s = 0.3);
  ~SerialTextEmulator();
  SerialTextEmulator(const SerialTextEmulator&) = delete;
  SerialTextEmulator& operator=(const SerialTextEmulator&) = delete;

  std::pair<double, double> wheels_mps() const;  // left, right, as driven
  int motor_commands() const;                    // `m` commands taken
  int invalid_commands() const;                  // commands answered "Invalid Command"

  // Faults: bytes of noise before the next answer; the next encoder answer with one byte lost; the next `n` encoder
  // answers never sent (lost on the line); every answer this much later; no answers (and deaf) until Resume; a restart
  // of the board with the port open (deaf for boot_s, then counting from zero, wheels stopped); the cable pulled, and
  // plugged back in (the board restarts).
  void Noise(std::string bytes);
  void DropAByte();
  void LoseReplies(int n);
  void Slow(double delay_s);
  void Silence();
  void Resume();
  void Restart();
  void Unplug();
  void Replug();

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(const std::string& command, double now_s);
  void Answer(std::string text, double now_s);
  void Boot(double now_s);

  mutable std::mutex mutex_;
  PseudoTerminal terminal_;
  SerialTextGeometry geometry_;
  double boot_s_;
  std::string received_;
  std::deque<std::pair<double, std::string>> answers_;  // when due, what
  double left_mps_ = 0.0;
  double right_mps_ = 0.0;
  double left_counts_ = 2147483647.0 - 3000.0;
  double right_counts_ = 2147483647.0 - 3000.0;
  int motor_commands_ = 0;
  int invalid_commands_ = 0;
  double last_motor_s_ = 0.0;
  double booted_s_ = 0.0;  // deaf until then
  std::string noise_;
  bool drop_a_byte_ = false;
  int replies_to_lose_ = 0;
  double delay_s_ = 0.0;
  bool silent_ = false;
  double last_s_ = 0.0;
  std::jthread thread_;
};

}  // namespace corridor::testing
