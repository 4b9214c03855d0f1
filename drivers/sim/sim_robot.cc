#include "drivers/sim/sim_robot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace corridor::drivers::sim {
namespace {

TimeNs PeriodNs(double rate_hz) { return static_cast<TimeNs>(1e9 / rate_hz); }

// True when a sensor with this rate is due at `now`; advances its schedule by whole periods so that the rate is
// kept exactly on average even when the period is not a multiple of the physics step.
bool Due(TimeNs now, double rate_hz, TimeNs& next_ns) {
  if (now < next_ns) return false;
  next_ns += PeriodNs(rate_hz);
  if (next_ns <= now) next_ns = now + PeriodNs(rate_hz);  // fell behind (a reset): do not burst
  return true;
}

}  // namespace

SimRobot::SimRobot(std::shared_ptr<const World> world, const SimOptions& options)
    : world_(std::move(world)),
      options_(options),
      caster_(world_->mesh),
      renderer_(caster_, options.camera),
      stereo_(options.stereo.enabled ? std::make_unique<SimStereoCamera>(caster_, options.camera, options.stereo)
                                     : nullptr),
      camera_info_(stereo_ ? stereo_->info() : MakeCameraInfo(options.camera)),
      rng_(options.seed),
      base_(world_->collision, options.base, options.start),
      crowd_(*world_, options.pedestrians, options.crowd),
      battery_(options.battery) {
  if (options.dock) dock_.emplace(*options.dock);
  for (const SimDoorOptions& d : options.doors) doors_.emplace_back(d);
  for (const SimLiftOptions& l : options.lifts) lifts_.emplace_back(l);
  ApplyDoors();
}

void SimRobot::ApplyDoors() {
  // Lock held (or not yet shared). What is solid: the dock and the closed doors.
  std::vector<Block> blocks;
  if (dock_) blocks.push_back(dock_->block());
  for (const SimDoor& d : doors_) {
    if (!d.open()) blocks.push_back(d.block());
  }
  for (const SimLift& l : lifts_) {
    for (const SimDoor& w : l.walls()) blocks.push_back(w.block());
    for (const SimDoor* d : l.closed_doors()) blocks.push_back(d->block());
  }
  base_.SetBlocks(std::move(blocks));
  doors_changed_ = false;
  movers_changed_ = true;
}

TriangleMesh SimRobot::MoversMesh() const {
  TriangleMesh mesh = crowd_.Mesh();
  for (const SimDoor& d : doors_) {
    if (!d.open()) mesh.Append(d.Mesh());
  }
  for (const SimLift& l : lifts_) {
    for (const SimDoor& w : l.walls()) mesh.Append(w.Mesh());
    for (const SimDoor* d : l.closed_doors()) mesh.Append(d->Mesh());
  }
  return mesh;
}

bool SimRobot::SetDoorOpen(const std::string& id, bool open) {
  std::lock_guard lock(mutex_);
  for (SimDoor& d : doors_) {
    if (d.id() != id) continue;
    if (d.open() != open) doors_changed_ = true;
    d.set_open(open);
    return true;
  }
  return false;
}

std::vector<std::pair<std::string, bool>> SimRobot::doors() const {
  std::lock_guard lock(mutex_);
  std::vector<std::pair<std::string, bool>> out;
  for (const SimDoor& d : doors_) out.emplace_back(d.id(), d.open());
  return out;
}

bool SimRobot::CallLift(const std::string& id, const std::string& floor) {
  std::lock_guard lock(mutex_);
  for (SimLift& l : lifts_) {
    if (l.id() != id) continue;
    doors_changed_ = true;
    if (floor.empty()) {
      l.Release();
      return true;
    }
    return l.Call(floor, ToSeconds(clock_.Now()));
  }
  return false;
}

std::vector<SimLiftState> SimRobot::lifts() const {
  std::lock_guard lock(mutex_);
  std::vector<SimLiftState> out;
  for (const SimLift& l : lifts_) out.push_back(l.state());
  return out;
}

BatteryState SimRobot::battery_state() const {
  std::lock_guard lock(mutex_);
  return battery_.State(clock_.Now());
}

std::vector<Pedestrian> SimRobot::pedestrians() const {
  std::lock_guard lock(mutex_);
  return crowd_.pedestrians();
}

bool SimRobot::bumper_pressed() const {
  std::lock_guard lock(mutex_);
  return base_.bumper_pressed();
}

nav::Pose2 SimRobot::true_pose() const {
  std::lock_guard lock(mutex_);
  return base_.pose();
}

void SimRobot::Teleport(const nav::Pose2& pose) {
  std::lock_guard lock(mutex_);
  base_.Teleport(pose);
}

PanLimits SimRobot::pan_limits() const {
  constexpr double kToRad = std::numbers::pi / 180.0;
  return {options_.pan.min_deg * kToRad, options_.pan.max_deg * kToRad, options_.pan.max_speed_dps * kToRad};
}

void SimRobot::SetTarget(double pan_rad) {
  const PanLimits l = pan_limits();
  if (std::isfinite(pan_rad)) pan_target_rad_ = std::clamp(pan_rad, l.min_rad, l.max_rad);
}

void SimRobot::StepPan(TimeNs now) {
  if (!options_.pan.enabled) return;
  const double pan = pan_rad_.load();
  const double step = std::clamp(pan_target_rad_.load() - pan, -pan_limits().max_speed_rps * step_s(),
                                 pan_limits().max_speed_rps * step_s());
  pan_rad_ = pan + step;
  pan_velocity_rps_ = step / step_s();
  // While it turns, a reading every step: a frame rendered at this step has its camera's angle at its stamp.
  if ((Due(now, options_.pan.rate_hz, next_pan_ns_) || step != 0.0) && pan_handler_ && !pan_stopped_) {
    pan_handler_(PanReading{now, pan_rad_.load(), pan_velocity_rps_});
  }
}

void SimRobot::SetVelocity(const nav::Twist2& command) {
  std::lock_guard lock(mutex_);
  pending_command_ = command;
  has_pending_command_ = true;
}

void SimRobot::Step() {
  ++step_count_;
  const TimeNs now = static_cast<TimeNs>(static_cast<double>(step_count_) * 1e9 / options_.physics_rate_hz);
  clock_.Set(now);
  const double now_s = ToSeconds(now);

  nav::Pose2 pose;
  WheelOdometry odometry;
  BatteryState battery;
  {
    std::lock_guard lock(mutex_);
    for (SimLift& l : lifts_) {
      const bool was_open = l.state().door_open;
      if (const std::optional<nav::Pose2> carried = l.Step(now_s, base_.pose())) base_.Teleport(*carried);
      doors_changed_ = doors_changed_ || l.state().door_open != was_open;
    }
    if (doors_changed_) ApplyDoors();
    if (has_pending_command_) base_.Command(pending_command_, now_s);
    has_pending_command_ = false;
    if (!crowd_.empty()) {
      // The robot as people see it: they take all of the avoidance.
      const nav::Pose2 at = base_.pose();
      const Eigen::Vector2d velocity =
          base_.velocity().linear_mps * Eigen::Vector2d(std::cos(at.yaw_rad), std::sin(at.yaw_rad));
      crowd_.Step(step_s(), OrcaNeighbour{at.translation(), velocity, options_.base.limits.footprint_radius_m, false});
      std::vector<Disc> people;
      for (const Pedestrian& p : crowd_.pedestrians()) people.push_back({p.position, options_.crowd.radius_m});
      base_.SetMovers(std::move(people));
    }
    base_.Step(step_s(), now_s, rng_);
    pose = base_.pose();
    battery_.Step(step_s(), base_.velocity(), dock_ && dock_->Contacts(pose));
    battery = battery_.State(now);
    odometry = {now, base_.odom_pose(), base_.velocity(), base_.bumper_pressed()};
  }

  StepPan(now);
  if (Due(now, options_.odometry_rate_hz, next_odometry_ns_)) {
    if (odometry_handler_) odometry_handler_(odometry);
  }
  if (Due(now, options_.battery.rate_hz, next_battery_ns_) && battery_handler_) battery_handler_(battery);
  const bool frame_due = Due(now, options_.camera.rate_hz, next_frame_ns_) && frame_handler_ && !camera_stopped_;
  const bool sweeping = options_.laser.enabled && options_.laser.sweep && scan_handler_;
  // A rotating laser casts a few beams every step; the moving things are redrawn for it at its rate, as for a scan.
  const bool scan_due =
      options_.laser.enabled && Due(now, options_.laser.rate_hz, next_scan_ns_) && (scan_handler_ || beams_cast_);
  if ((!crowd_.empty() || movers_changed_) && (frame_due || scan_due)) {
    std::lock_guard lock(mutex_);
    caster_.SetMovers(MoversMesh());
    movers_changed_ = false;
  }
  if (frame_due) {
    auto frame = std::make_shared<RgbdFrame>();
    frame->stamp_ns = now;
    frame->sequence = frame_sequence_++;
    // The camera turned by the pan servo is the camera at rest on a base turned about the servo's axis.
    Eigen::Isometry3d world_T_base = pose.ToIsometry3();
    if (options_.pan.enabled) world_T_base = world_T_base * nav::PanTurn(axis_xy(), pan_rad_.load());
    if (stereo_) {
      stereo_->Render(world_T_base, rng_, *frame);
    } else {
      renderer_.Render(world_T_base * camera_info_.camera.base_T_camera, rng_, *frame);
    }
    frame_handler_(std::move(frame));
  }
  if (sweeping) {
    SweepLaser(now, pose);
  } else if (scan_due && scan_handler_) {
    auto scan = std::make_shared<LaserScan>();
    scan->stamp_ns = now;
    Eigen::Isometry3d world_T_laser = pose.ToIsometry3();
    world_T_laser.translation().z() = options_.laser.mount_height_m;
    CastScan(caster_, world_T_laser, options_.laser, rng_, *scan);
    scan_handler_(std::move(scan));
  }
}

float SimRobot::CastLaserBeam(double clockwise_rad) {
  beams_cast_ = true;
  Eigen::Isometry3d world_T_laser = true_pose().ToIsometry3();
  world_T_laser.translation().z() = options_.laser.mount_height_m;
  const Eigen::Vector3f direction =
      world_T_laser.linear().cast<float>() *
      Eigen::Vector3f(static_cast<float>(std::cos(-clockwise_rad)), static_cast<float>(std::sin(-clockwise_rad)), 0.0f);
  const RayHit hit =
      caster_.Cast(world_T_laser.translation().cast<float>(), direction, static_cast<float>(options_.laser.min_range_m),
                   static_cast<float>(options_.laser.max_range_m));
  std::normal_distribution<float> noise(0.0f, static_cast<float>(options_.laser.noise_m));
  return hit.hit() ? hit.distance + noise(rng_) : std::numeric_limits<float>::infinity();
}

void SimRobot::SweepLaser(TimeNs now, const nav::Pose2& pose) {
  const SimLaserOptions& laser = options_.laser;
  const TimeNs period_ns = PeriodNs(laser.rate_hz);
  if (sweep_start_ns_ < 0 || now - sweep_start_ns_ > 2 * period_ns) sweep_start_ns_ = now;  // first, or a reset
  Eigen::Isometry3d world_T_laser = pose.ToIsometry3();
  world_T_laser.translation().z() = laser.mount_height_m;
  while (true) {
    if (!sweep_) {
      sweep_ = std::make_shared<LaserScan>();
      StartScan(laser, *sweep_);
      sweep_done_ = 0;
    }
    // Beam k is measured k / beams of the turn after the sweep began.
    const double turned = static_cast<double>(now - sweep_start_ns_) / static_cast<double>(period_ns);
    const int due = std::min(laser.beams, static_cast<int>(std::floor(turned * laser.beams)) + 1);
    CastBeams(caster_, world_T_laser, laser, rng_, sweep_done_, due, *sweep_);
    sweep_done_ = std::max(sweep_done_, due);
    if (sweep_done_ < laser.beams) return;
    sweep_->stamp_ns = sweep_start_ns_ + period_ns;  // when the turn ended, its last beam just before
    sweep_->sweep_s = ToSeconds(period_ns);
    sweep_->sweep_start_rad = 0.0;
    sweep_->sweep_clockwise = true;
    scan_handler_(std::move(sweep_));
    sweep_.reset();
    sweep_start_ns_ += period_ns;
  }
}

}  // namespace corridor::drivers::sim
