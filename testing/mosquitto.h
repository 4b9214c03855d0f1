// For tests: a mosquitto broker this process runs on loopback (a plain listener on a port of its own, anonymous,
// nothing persisted), stopped with the object. Debian's mosquitto package; the broker dies with the test process.
#pragma once

#include <sys/types.h>

#include <string>

#include "testing/temp_dir.h"

namespace corridor::testing {

class Mosquitto {
 public:
  // Starts the broker and waits until it takes connections; throws std::runtime_error when it does not within 10 s.
  Mosquitto();
  ~Mosquitto();
  Mosquitto(const Mosquitto&) = delete;
  Mosquitto& operator=(const Mosquitto&) = delete;

  // mqtt://127.0.0.1:port
  std::string url() const;
  int port() const { return port_; }

 private:
  TempDir dir_{"corridor_mosquitto"};
  int port_ = 0;
  pid_t pid_ = -1;
};

}  // namespace corridor::testing
