// A TurtleBot 3 laser for tests, on a pseudo-terminal: an LDS-02 (LDROBOT LD08: 47-byte packets of 12 points with a
// CRC-8, sent from power-up) or an LDS-01 (Hitachi-LG HLS-LFCD2: 42-byte packets of 6 readings, sent between the
// host's 'b' and 'e'), written from their documents apart from the driver's codec, and the faults real devices show:
// noise, a packet whose check fails, a byte lost, silence, unplugging and plugging back in under the same path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

struct LdsEmulatorOptions {
  bool lds01 = false;           // an LDS-01; else an LDS-02
  double revolutions_hz = 6.0;  // an LDS-02 turns at about 6 Hz, an LDS-01 at 5
  // The distance in metres at an angle clockwise from the device's forward (degrees); 0: nothing measured.
  std::function<double(double)> range = [](double) { return 2.0; };
};

class LdsEmulator {
 public:
  // Serves a new pseudo-terminal whose slave `link` points to.
  LdsEmulator(std::filesystem::path link, LdsEmulatorOptions options);
  ~LdsEmulator();
  LdsEmulator(const LdsEmulator&) = delete;
  LdsEmulator& operator=(const LdsEmulator&) = delete;

  // Faults, each played once at the next packet: bytes of noise before it, one of its bytes corrupted (an LDS-02's
  // CRC fails; an LDS-01's index byte, the one its data table gives a range for), one of its bytes left out.
  void Noise(std::vector<std::uint8_t> bytes);
  void Corrupt();
  void DropByte();
  // Stops sending (the port stays open) until Resume.
  void Silence();
  void Resume();
  // The cable pulled: the pseudo-terminal closed and the link removed. Replug: a new one under the same link, the
  // device powered up anew (an LDS-01 waits for 'b' again).
  void Unplug();
  void Replug();

  bool sending() const;  // an LDS-02 always; an LDS-01 after 'b' until 'e'
  int starts() const;    // the 'b's an LDS-01 received

 private:
  void Serve(std::stop_token stop);
  void Step();
  std::vector<std::uint8_t> Packet(int index) const;  // the revolution's index-th packet
  int PacketsPerRevolution() const { return options_.lds01 ? 60 : 30; }

  LdsEmulatorOptions options_;
  mutable std::mutex mutex_;  // guards everything below
  PseudoTerminal terminal_;
  bool started_ = false;  // an LDS-01's 'b'
  bool silent_ = false;
  int starts_ = 0;
  int next_packet_ = 0;
  double sent_until_s_ = 0.0;
  std::vector<std::uint8_t> noise_;
  bool corrupt_ = false;
  bool drop_byte_ = false;
  std::jthread thread_;
};

}  // namespace corridor::testing
