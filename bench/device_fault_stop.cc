// How fast a device that stops answering stops the robot (issue 37's budget: zero forward command within 100 ms of
// the device's last data). corridord on native drivers (tests/dds/native_robot.h: a Create 2 and an RPLIDAR on their
// emulators' pseudo-terminals, a camera over DDS) is driven forward at 0.2 m/s by teleop; then the laser falls silent
// (or is unplugged), and the time from its last byte to the first lower Drive Direct command the emulated Create 2
// receives is measured (the driver then ramps the wheels down at the base's deceleration). Trials alternate with the
// device coming back and the robot driving again.
//   device_fault_stop [TRIALS]      (TRACE=1: each trial's wheel speeds on stderr)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "tests/dds/native_robot.h"

using namespace corridor::testing;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

// Milliseconds from `fault` (played at once) to the wheels' first slower command; negative: none within 2 s.
double TimeToStop(NativeRobot& robot, const std::function<void()>& fault) {
  // At the asked speed (the wheels ramp: a robot still slowing from the last trial would be no trial at all).
  if (!robot.Until(true, 10s, [&] { return robot.base().wheels_mmps().first >= 200; })) return -1.0;
  const int steady = robot.base().wheels_mmps().first;
  const auto start = Clock::now();
  fault();
  auto next_teleop = start;
  while (Clock::now() - start < 2s) {
    if (std::getenv("TRACE") != nullptr) {
      std::fprintf(stderr, "%.1f ms %d\n", std::chrono::duration<double, std::milli>(Clock::now() - start).count(),
                   robot.base().wheels_mmps().first);
    }
    if (robot.base().wheels_mmps().first < steady) {
      return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    }
    if (Clock::now() >= next_teleop) {  // the operator keeps asking to drive on
      robot.daemon().Call("POST", "/api/v1/teleop", {{"linear_mps", 0.2}, {"angular_rps", 0.0}});
      next_teleop += 100ms;
    }
    std::this_thread::sleep_for(200us);
  }
  return -1.0;
}

void Report(const char* what, std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  const int failed = static_cast<int>(std::count_if(ms.begin(), ms.end(), [](double t) { return t < 0.0; }));
  ms.erase(ms.begin(), ms.begin() + failed);
  if (ms.empty()) {
    std::printf("%-22s no stop seen in %d trials\n", what, failed);
    return;
  }
  std::printf("%-22s %zu trials: median %.1f ms, max %.1f ms%s\n", what, ms.size(), ms[ms.size() / 2], ms.back(),
              failed > 0 ? (", " + std::to_string(failed) + " without a stop").c_str() : "");
}

}  // namespace

int main(int argc, char** argv) {
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  NativeRobot robot(CORRIDORD, CORRIDOR_SOURCE_DIR, Domain(20));
  if (!robot.Until(false, 20s, [&] { return robot.AllOk(); })) {
    std::fprintf(stderr, "the devices never came up:\n%s\n", robot.daemon().log().c_str());
    return 1;
  }
  std::vector<double> silent, unplugged;
  for (int i = 0; i < trials; ++i) {
    silent.push_back(TimeToStop(robot, [&] { robot.laser().Silence(); }));
    robot.laser().Resume();
    unplugged.push_back(TimeToStop(robot, [&] { robot.laser().Unplug(); }));
    robot.laser().Replug();
  }
  Report("laser silent", silent);
  Report("laser unplugged", unplugged);
  return 0;
}
