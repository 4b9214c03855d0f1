// A TurtleBot 3's OpenCR board for tests, on a pseudo-terminal: a DYNAMIXEL Protocol 2.0 device 200
// (dynamixel_emulator.h, with its faults) holding the board's TurtleBot 3 control table as the e-Manual gives it
// (buttons, bumpers, battery, the wheels' velocities and positions, torque, the velocity command). With torque on, the
// wheels turn at the commanded velocity at once; their positions count 4096 a turn of a 66 mm wheel, 160 mm apart (a
// Burger), as int32 starting near their wrap. Replugged, the board has restarted: torque off, still.
#pragma once

#include <filesystem>
#include <utility>

#include "testing/emulators/dynamixel_emulator.h"

namespace corridor::testing {

class OpenCrEmulator final : public DynamixelEmulator {
 public:
  explicit OpenCrEmulator(std::filesystem::path link);
  ~OpenCrEmulator() override;

  std::pair<double, double> wheels_mps() const;  // left, right, as driven
  bool torque() const;
  int heartbeats() const;  // writes to the heartbeat
  void SetBumper(bool pressed);
  void SetBattery(double volts, double percent);

 private:
  void Advance(double dt_s) override;
  void Written(std::size_t address, std::size_t length) override;
  void Restarted() override;  // torque off, still

  double left_mps_ = 0.0;
  double right_mps_ = 0.0;
  double left_ticks_ = 2147483647.0 - 2000.0;
  double right_ticks_ = 2147483647.0 - 2000.0;
  int heartbeats_ = 0;
};

}  // namespace corridor::testing
