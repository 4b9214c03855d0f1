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
  base_ = std::make_unique<Create2Emulator>(create2, Pace::kOwner);
  robot.SetBatteryHandler([this](const drivers::BatteryState& b) {
    base_->SetBattery(static_cast<int>(std::lround(b.charge * kCapacityMah)), kCapacityMah, b.on_charger);
  });
  RplidarEmulatorOptions lidar;
  lidar.revolutions_hz = config.sim.robot.laser.rate_hz;
  lidar.samples = config.sim.robot.laser.beams;
  lidar.range = [this](double clockwise_deg) { return RangeAt(clockwise_deg); };
  lidar.pace = Pace::kOwner;
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

double EmulatedRobot::RangeAt(double clockwise_deg) {
  const float r = sim_.robot->CastLaserBeam(clockwise_deg * std::numbers::pi / 180.0);
  return std::isfinite(r) && r > 0.0f ? r : 0.0;  // no return: nothing measured
}

void EmulatedRobot::Run(std::stop_token stop) {
  drivers::sim::SimRobot& robot = *sim_.robot;
  const auto step = std::chrono::nanoseconds(drivers::FromSeconds(robot.step_s()));
  auto next = std::chrono::steady_clock::now();
  while (!stop.stop_requested()) {
    const auto [left_mmps, right_mmps] = base_->wheels_mmps();
    robot.SetVelocity({(left_mmps + right_mmps) / 2000.0, (right_mmps - left_mmps) / 1000.0 / kTrackM});
    robot.Step();
    // The devices in the simulator's time: the wheels counted over the step the body moved, the beams due cast from
    // where it is now.
    const double now_s = drivers::ToSeconds(robot.now_ns());
    base_->Tick(now_s);
    laser_->Tick(now_s);
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
