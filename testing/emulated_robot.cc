#include "testing/emulated_robot.h"

#include <chrono>
#include <cmath>
#include <numbers>

namespace corridor::testing {
namespace {

// The Create 2's wheels, as its Open Interface document gives them: 235 mm apart.
constexpr double kTrackM = 0.235;
constexpr int kCapacityMah = 2696;
// Behind real time by more than this (the machine was busy), the simulator catches up at once instead of racing.
constexpr auto kMaxLag = std::chrono::milliseconds(200);

}  // namespace

EmulatedRobot::EmulatedRobot(server::Config config, const std::filesystem::path& create2,
                             const std::filesystem::path& rplidar) {
  // The simulator's robot, with its laser, whatever devices the configuration gives corridord.
  config.devices = server::DevicesOptions{};
  config.sim.robot.laser.enabled = true;
  sim_ = server::MakeSimulator(config);
  drivers::sim::SimRobot& robot = *sim_.robot;
  robot.SetScanHandler([this](std::shared_ptr<const drivers::LaserScan> scan) {
    std::lock_guard lock(mutex_);
    scan_ = std::move(scan);
  });
  base_ = std::make_unique<Create2Emulator>(create2);
  robot.SetBatteryHandler([this](const drivers::BatteryState& b) {
    base_->SetBattery(static_cast<int>(std::lround(b.charge * kCapacityMah)), kCapacityMah, b.on_charger);
  });
  RplidarEmulatorOptions lidar;
  lidar.revolutions_hz = config.sim.robot.laser.rate_hz;
  lidar.samples = config.sim.robot.laser.beams;
  lidar.range = [this](double clockwise_deg) { return RangeAt(clockwise_deg); };
  laser_ = std::make_unique<RplidarEmulator>(rplidar, std::move(lidar));
  thread_ = std::jthread([this](std::stop_token stop) { Run(std::move(stop)); });
}

EmulatedRobot::~EmulatedRobot() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
  laser_.reset();
  base_.reset();
}

nav::Pose2 EmulatedRobot::true_pose() const { return sim_.robot->true_pose(); }

bool EmulatedRobot::bumped() const {
  std::lock_guard lock(mutex_);
  return bumped_;
}

double EmulatedRobot::RangeAt(double clockwise_deg) const {
  std::shared_ptr<const drivers::LaserScan> scan;
  {
    std::lock_guard lock(mutex_);
    scan = scan_;
  }
  if (!scan || scan->ranges.empty() || !(scan->angle_increment_rad > 0.0)) return 0.0;
  // The RPLIDAR measures clockwise from its forward; the simulated laser's sweep runs counter-clockwise (REP-103).
  const double angle = -clockwise_deg * std::numbers::pi / 180.0;
  const double turn = 2.0 * std::numbers::pi;
  const double from_min = std::fmod(std::fmod(angle - scan->angle_min_rad, turn) + turn, turn);
  const auto n = static_cast<long>(scan->ranges.size());
  const long i = std::lround(from_min / scan->angle_increment_rad) % n;
  const double r = scan->ranges[static_cast<std::size_t>(i)];
  return std::isfinite(r) && r > 0.0 ? r : 0.0;  // no return: nothing measured
}

void EmulatedRobot::Run(std::stop_token stop) {
  drivers::sim::SimRobot& robot = *sim_.robot;
  const auto step = std::chrono::nanoseconds(drivers::FromSeconds(robot.step_s()));
  auto next = std::chrono::steady_clock::now();
  while (!stop.stop_requested()) {
    const auto [left_mmps, right_mmps] = base_->wheels_mmps();
    robot.SetVelocity({(left_mmps + right_mmps) / 2000.0, (right_mmps - left_mmps) / 1000.0 / kTrackM});
    robot.Step();
    const bool pressed = robot.bumper_pressed();
    base_->SetBump(pressed);
    if (pressed) {
      std::lock_guard lock(mutex_);
      bumped_ = true;
    }
    next += step;
    const auto now = std::chrono::steady_clock::now();
    if (now - next > kMaxLag) next = now;
    std::this_thread::sleep_until(next);  // the simulator's pace: real time
  }
}

}  // namespace corridor::testing
