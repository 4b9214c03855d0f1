// An iRobot Create 2 for tests, on a pseudo-terminal: the robot's side of iRobot's "Create 2 Open Interface (OI)
// Specification" (Start, Safe, Full, Stop, Reset, Drive Direct, Stream, Pause/Resume Stream; the stream's frames every
// 15 ms with the packets asked for), written from that document apart from the driver's codec. The wheels turn at
// the commanded speeds and their encoders count (508.8 a turn of a 72 mm wheel, wrapping at 65535); Safe mode stops
// the wheels and falls back to Passive on a cliff or a dropped wheel, as the document says. Faults: noise, a frame
// with a bad checksum, silence, unplugging and plugging back in under the same path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include "testing/emulators/device_end.h"
#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

class Create2Emulator {
 public:
  // Serves a new pseudo-terminal whose slave `link` points to, paced by `pace` (device_end.h).
  explicit Create2Emulator(std::filesystem::path link, Pace pace = Pace::kOwnThread);
  ~Create2Emulator();
  Create2Emulator(const Create2Emulator&) = delete;
  Create2Emulator& operator=(const Create2Emulator&) = delete;

  // Pace::kOwner: one turn of the robot at `now_s` of the owner's clock (commands taken, wheels counted since the
  // turn before, a frame sent when one is due). Thread-safe.
  void Tick(double now_s);

  // The robot's state.
  int mode() const;                         // 0 off, 1 passive, 2 safe, 3 full
  std::pair<int, int> wheels_mmps() const;  // left, right, as driven
  void SetCliff(bool cliff);
  void SetBump(bool bump);
  void SetBattery(int charge_mah, int capacity_mah, bool on_home_base);
  // Faults: bytes of noise before the next frame; the next frame's checksum wrong; no frames (and deaf) until
  // Resume; the cable pulled, and plugged back in (the robot powered up anew: OI off).
  void Noise(std::vector<std::uint8_t> bytes);
  void BadChecksum();
  void Silence();
  void Resume();
  void Unplug();
  void Replug();

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(const std::vector<std::uint8_t>& command);
  std::vector<std::uint8_t> Frame() const;

  mutable std::mutex mutex_;
  PseudoTerminal terminal_;
  std::vector<std::uint8_t> received_;
  int mode_ = 0;
  int left_mmps_ = 0;
  int right_mmps_ = 0;
  double left_counts_ = 65000.0;  // near the wrap, so that tests cross it
  double right_counts_ = 65000.0;
  std::vector<std::uint8_t> streamed_;  // packet ids
  bool streaming_ = false;
  bool cliff_ = false;
  bool bump_ = false;
  int charge_mah_ = 2000;
  int capacity_mah_ = 2696;
  bool home_base_ = false;
  std::vector<std::uint8_t> noise_;
  bool bad_checksum_ = false;
  bool silent_ = false;
  double last_s_ = 0.0;
  double next_frame_s_ = 0.0;
  std::jthread thread_;
};

}  // namespace corridor::testing
