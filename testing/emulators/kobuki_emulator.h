// A Kobuki for tests, on a pseudo-terminal: the robot's side of Yujin Robot's "Kobuki Protocol Specification"
// (packets of 0xAA 0x55, a length, sub-payloads and an XOR checksum; Base Control taken; Basic Sensor Data, Inertial
// Sensor and Current streamed every 20 ms without being asked), written from that document apart from the driver's
// codec. The wheels turn as Base Control says (an arc's outer wheel at its speed; radius 0 straight, 1 on the spot) and
// keep turning until told otherwise; the encoders count 2578.33 a turn of a 70 mm wheel, wrapping at 65535. Faults:
// noise, a packet with a bad checksum, silence, unplugging and plugging back in under the same path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

class KobukiEmulator {
 public:
  explicit KobukiEmulator(std::filesystem::path link);
  ~KobukiEmulator();
  KobukiEmulator(const KobukiEmulator&) = delete;
  KobukiEmulator& operator=(const KobukiEmulator&) = delete;

  // The robot's state.
  std::pair<double, double> wheels_mps() const;  // left, right, as driven
  int base_controls() const;                     // Base Control commands taken
  void SetCliff(bool cliff);
  void SetBump(bool bump);
  void SetWheelDrop(bool dropped);
  void SetBattery(double volts, int charger);  // charger: the protocol's code (0, 2, 6, 18, 22)

  // Faults: bytes of noise before the next packet; the next packet's checksum wrong; no packets (and deaf) until
  // Resume; the cable pulled, and plugged back in (the robot as it was, its wheels stopped).
  void Noise(std::vector<std::uint8_t> bytes);
  void BadChecksum();
  void Silence();
  void Resume();
  void Unplug();
  void Replug();

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(std::uint8_t id, const std::uint8_t* data, std::size_t length);
  std::vector<std::uint8_t> Packet() const;

  mutable std::mutex mutex_;
  PseudoTerminal terminal_;
  std::vector<std::uint8_t> received_;
  double left_mps_ = 0.0;
  double right_mps_ = 0.0;
  int base_controls_ = 0;
  double left_counts_ = 65000.0;  // near the wrap, so that tests cross it
  double right_counts_ = 65000.0;
  double heading_rad_ = 0.0;
  bool cliff_ = false;
  bool bump_ = false;
  bool wheel_drop_ = false;
  double battery_v_ = 15.8;
  int charger_ = 0;
  std::vector<std::uint8_t> noise_;
  bool bad_checksum_ = false;
  bool silent_ = false;
  double start_s_ = 0.0;
  double last_s_ = 0.0;
  double next_packet_s_ = 0.0;
  std::jthread thread_;
};

}  // namespace corridor::testing
