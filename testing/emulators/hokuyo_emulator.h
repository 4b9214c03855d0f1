// A Hokuyo scanner for tests: the device's side of "URG Series Communication Protocol Specification SCIP 2.0" (SCIP2.0,
// VV, PP, II, BM, QT, RS, MD; echoes, status lines and data lines with their check characters, 3-character ranges cut
// into lines of 64), written from that document apart from the driver's codec, on a pseudo-terminal (a URG-04LX's USB
// serial port) or a TCP port on 127.0.0.1 (a UST-10LX's Ethernet). Faults: noise, a data line with a wrong check
// character, a lost byte, silence, unplugging and plugging back in.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "testing/emulators/device_end.h"

namespace corridor::testing {

struct HokuyoModel {
  std::string name;
  int dmin_mm, dmax_mm, ares, amin, amax, afrt, scan_rpm;
};
// Their documents' parameters: the URG-04LX (240 degrees, 10 scans a second) and the UST-10LX (270, 40).
HokuyoModel Urg04lx();
HokuyoModel Ust10lx();

struct HokuyoEmulatorOptions {
  HokuyoModel model = Urg04lx();
  // The distance in metres at an angle counter-clockwise from the device's front (radians); 0: nothing measured
  // (answered as the error code 1).
  std::function<double(double)> range = [](double) { return 2.0; };
};

class HokuyoEmulator {
 public:
  // On a pseudo-terminal whose slave `link` points to.
  HokuyoEmulator(std::filesystem::path link, HokuyoEmulatorOptions options);
  // On 127.0.0.1:port() (a free port).
  explicit HokuyoEmulator(HokuyoEmulatorOptions options);
  ~HokuyoEmulator();
  HokuyoEmulator(const HokuyoEmulator&) = delete;
  HokuyoEmulator& operator=(const HokuyoEmulator&) = delete;

  int port() const { return port_; }  // TCP only
  int scans_sent() const;
  bool laser_on() const;

  // Faults, each once at the next scan: noise before it, a data line's check character wrong, one byte of it lost.
  void Noise(std::string bytes);
  void BadCheck();
  void DropByte();
  // Stops answering and sending (the link stays up) until Resume.
  void Silence();
  void Resume();
  // The cable pulled, and plugged back in: the device powered up anew (laser off, not streaming).
  void Unplug();
  void Replug();

 private:
  void Start();
  void Serve(std::stop_token stop);
  void Step(double now_s);
  void Handle(const std::string& command);
  void Answer(const std::string& echo, const std::string& status, const std::vector<std::string>& lines = {});
  std::string Scan(double now_s);

  HokuyoEmulatorOptions options_;
  mutable std::mutex mutex_;
  std::unique_ptr<DeviceEnd> end_;
  int port_ = 0;
  std::string received_;
  bool laser_on_ = false;
  bool streaming_ = false;
  std::string md_echo_;
  int md_first_ = 0, md_last_ = 0, md_cluster_ = 1;
  double next_scan_s_ = 0.0;
  double start_s_ = 0.0;
  int scans_sent_ = 0;
  std::string noise_;
  bool bad_check_ = false;
  bool drop_byte_ = false;
  bool silent_ = false;
  std::jthread thread_;
};

}  // namespace corridor::testing
