// A DYNAMIXEL Protocol 2.0 device for tests, on a pseudo-terminal, as ROBOTIS's e-Manual documents the protocol
// (framing, byte stuffing, CRC-16/0x8005; Ping, Read, Write, Reboot; a status packet for each, with the error byte set
// for a bad CRC, an unknown instruction or an address out of the table), written from that document apart from the
// drivers' codec. A device (the OpenCR board, an X-series servo) supplies its control table's size and contents and
// what happens in it as time passes and when it is written. Faults: noise, an answer with a bad CRC, a slow device,
// silence, unplugging and plugging back in under the same path.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <span>
#include <thread>
#include <utility>
#include <vector>

#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

class DynamixelEmulator {
 public:
  DynamixelEmulator(const DynamixelEmulator&) = delete;
  DynamixelEmulator& operator=(const DynamixelEmulator&) = delete;
  virtual ~DynamixelEmulator() = default;

  int crc_errors() const;  // instruction packets refused for their CRC
  int reboots() const;     // Reboot instructions obeyed

  // Faults: bytes of noise before the next answer; the next answer's CRC wrong; every answer this much later; no
  // answers (and deaf) until Resume; the cable pulled, and plugged back in (the device restarted: Restarted).
  void Noise(std::vector<std::uint8_t> bytes);
  void BadCrc();
  void Slow(double delay_s);
  void Silence();
  void Resume();
  void Unplug();
  void Replug();

 protected:
  // Device `id`, its control table `table_size` bytes long (all 0 until the device fills them in).
  DynamixelEmulator(std::filesystem::path link, std::uint8_t id, std::size_t table_size);
  // The device's thread, serving the host: a device's constructor calls Start last, its destructor Stop first (the
  // thread calls its virtual functions).
  void Start();
  void Stop();

  // With mutex_ held. Time passing (seconds since the last call): the device moves, its present values change.
  virtual void Advance(double dt_s) = 0;
  // A write of `data` at `address` to come: the error byte to refuse it with (0: accepted, then stored).
  virtual std::uint8_t Check(std::size_t address, std::span<const std::uint8_t> data) const {
    (void)address;
    (void)data;
    return 0;
  }
  // After a write was stored.
  virtual void Written(std::size_t address, std::size_t length) {
    (void)address;
    (void)length;
  }
  // Power-cycled (replugged, or rebooted): its RAM back to the defaults.
  virtual void Restarted() {}
  // The error byte's top bit in every answer (a hardware error the device keeps until restarted).
  virtual bool alert() const { return false; }

  std::int32_t Int32At(std::size_t address) const;
  void SetInt32(std::size_t address, std::int32_t value);

  mutable std::mutex mutex_;
  std::vector<std::uint8_t> table_;

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(std::uint8_t instruction, const std::vector<std::uint8_t>& parameters, double now_s);
  void Answer(std::uint8_t error, const std::vector<std::uint8_t>& parameters, double now_s);

  const std::uint8_t id_;
  PseudoTerminal terminal_;
  std::vector<std::uint8_t> received_;
  std::deque<std::pair<double, std::vector<std::uint8_t>>> answers_;  // when due, what
  int crc_errors_ = 0;
  int reboots_ = 0;
  std::vector<std::uint8_t> noise_;
  bool bad_crc_ = false;
  double delay_s_ = 0.0;
  bool silent_ = false;
  double last_s_ = 0.0;
  std::jthread thread_;
};

}  // namespace corridor::testing
