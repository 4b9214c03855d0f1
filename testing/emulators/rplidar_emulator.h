// An RPLIDAR for tests, on a pseudo-terminal: the device's side of Slamtec's "RPLIDAR Interface Protocol and
// Application Notes" (GET_INFO, GET_HEALTH, RESET, SCAN, EXPRESS_SCAN, STOP; the standard scan's 5-byte nodes and the
// legacy express scan's 84-byte capsules of 32 samples, each with an angle correction, at the device's rate),
// written from that document apart from the driver's codec, and the faults real devices show: noise, a node with a
// bad check bit, a byte lost, silence, an error state that a reset clears, unplugging and plugging back in under the
// same path (a symbolic link, as udev's stable names are).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "testing/emulators/device_end.h"
#include "testing/emulators/pseudo_terminal.h"

namespace corridor::testing {

struct RplidarEmulatorOptions {
  double revolutions_hz = 10.0;
  int samples = 360;  // measurements a revolution, evenly spaced
  // The distance in metres at an angle clockwise from the device's forward (degrees), measured as the sample is sent;
  // 0: nothing measured. Called on the thread that paces the device.
  std::function<double(double)> range = [](double) { return 2.0; };
  Pace pace = Pace::kOwnThread;  // device_end.h
  int health_status = 0;         // 0 good, 1 warning, 2 error (until a RESET)
};

class RplidarEmulator {
 public:
  // Serves a new pseudo-terminal whose slave `link` points to.
  RplidarEmulator(std::filesystem::path link, RplidarEmulatorOptions options);
  ~RplidarEmulator();
  RplidarEmulator(const RplidarEmulator&) = delete;
  RplidarEmulator& operator=(const RplidarEmulator&) = delete;

  // Pace::kOwner: one turn of the device at `now_s` of the owner's clock (requests answered, the samples due since the
  // turn before sent). Thread-safe.
  void Tick(double now_s);

  // Faults, each played once at the next node or capsule: bytes of noise before it, its check bit cleared (a capsule:
  // its checksum wrong), one of its bytes left out.
  void Noise(std::vector<std::uint8_t> bytes);
  void BadCheckBit();
  void DropByte();
  // Stops answering and sending (the port stays open) until Resume.
  void Silence();
  void Resume();
  // The cable pulled: the pseudo-terminal closed and the link removed. Replug: a new one under the same link, the
  // device powered up anew (not scanning).
  void Unplug();
  void Replug();

  int scans_started() const { return scans_started_.load(); }
  int express_scans_started() const { return express_scans_started_.load(); }
  int resets() const { return resets_.load(); }

 private:
  void Serve(std::stop_token stop);
  void Step(double now_s);  // one turn of the device: requests answered, the samples due by now_s sent
  void Handle(std::uint8_t command, double now_s);
  // SCAN (nodes) or EXPRESS_SCAN (capsules) answered and begun, unless the device is in error.
  void StartScan(bool express, double now_s);
  void Send(const std::vector<std::uint8_t>& bytes) { terminal_.Send(bytes); }
  void SendNode(int index);
  void SendCapsule(int first_index);  // samples first_index.. first_index + 31
  void SendWithFaults(std::vector<std::uint8_t> bytes, std::size_t check_byte, std::uint8_t check_mask);

  RplidarEmulatorOptions options_;
  std::mutex mutex_;  // guards everything below but the counters
  PseudoTerminal terminal_;
  bool scanning_ = false;
  bool express_ = false;  // scanning in capsules
  bool first_capsule_ = false;
  bool silent_ = false;
  int health_status_ = 0;
  int next_sample_ = 0;
  double sent_until_s_ = 0.0;  // the emulator's time, in revolutions' worth of samples sent
  std::vector<std::uint8_t> noise_;
  bool bad_check_ = false;
  bool drop_byte_ = false;
  std::vector<std::uint8_t> request_;  // a request being received
  std::atomic<int> scans_started_{0};
  std::atomic<int> express_scans_started_{0};
  std::atomic<int> resets_{0};
  std::jthread thread_;
};

}  // namespace corridor::testing
