// The simulated robot: one object that is the DepthCamera, the DiffDriveBase and the Laser2D of a robot driving
// in a World. Time advances only through Step(), so the owner decides between real time (the daemon's sim executor
// steps it on a timer) and lockstep faster than real time (tools and tests call Step in a loop).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>

#include "drivers/battery.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "drivers/pan_servo.h"
#include "drivers/sim/battery_sim.h"
#include "drivers/sim/crowd.h"
#include "drivers/sim/diff_drive_sim.h"
#include "drivers/sim/dock.h"
#include "drivers/sim/door.h"
#include "drivers/sim/lift.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/sensors.h"
#include "drivers/sim/sim_stereo.h"
#include "drivers/sim/world.h"

namespace corridor::drivers::sim {

struct SimOptions {
  nav::Pose2 start;                // initial pose in the world frame
  double physics_rate_hz = 100.0;  // kinematics and collision steps per simulated second
  double odometry_rate_hz = 50.0;
  std::uint32_t seed = 1;  // all noise is drawn from one generator seeded with this
  SimBaseOptions base;
  SimCameraOptions camera;
  SimStereoOptions stereo;  // the camera as a stereo pair (sim.camera.stereo)
  SimPanOptions pan;        // the camera on a pan servo (sim.camera.pan)
  SimLaserOptions laser;
  std::vector<PedestrianRoute> pedestrians;  // people walking back and forth, not seeing the robot
  CrowdOptions crowd;
  SimBatteryOptions battery;
  std::optional<SimDockOptions> dock;  // a charging dock; its box must be in the world (AddDock)
  std::vector<SimDoorOptions> doors;   // doors across passages, opened and closed through SetDoorOpen
  std::vector<SimLiftOptions> lifts;   // lifts between floors standing side by side, called through CallLift
};

class SimRobot final : public DepthCamera, public DiffDriveBase, public Laser2D, public Battery, public PanServo {
 public:
  // `world` must outlive the robot.
  SimRobot(std::shared_ptr<const World> world, const SimOptions& options);

  // Advances simulated time by one physics step, delivering odometry, frames and scans that fall due, on the
  // caller's thread. Must be called from one thread at a time.
  void Step();
  TimeNs now_ns() const { return clock_.Now(); }
  // Simulated time: what a graph run in lockstep with this robot takes as its clock.
  const Clock& clock() const { return clock_; }
  double step_s() const { return 1.0 / options_.physics_rate_hz; }

  // One beam of the laser, `clockwise_rad` clockwise from its forward, measured now from where the robot truly is (with
  // the laser's noise): a rotating laser emulated beam by beam as it turns. +infinity for no return. From the first
  // call on, the moving things are redrawn for such beams at the laser's rate. Call on the stepping thread, between
  // Steps.
  float CastLaserBeam(double clockwise_rad);

  // Ground truth, for the console and for tests. Thread-safe.
  nav::Pose2 true_pose() const;
  std::vector<Pedestrian> pedestrians() const;
  // A simulated fault: the camera stops delivering frames (true) or resumes (false). Thread-safe.
  void SetCameraStopped(bool stopped) { camera_stopped_ = stopped; }
  bool camera_stopped() const { return camera_stopped_; }
  // A simulated fault: the pan servo's readings stop (true: it still turns, nobody hears where) or resume.
  // Thread-safe.
  void SetPanStopped(bool stopped) { pan_stopped_ = stopped; }
  double pedestrian_radius_m() const { return options_.crowd.radius_m; }
  bool bumper_pressed() const;
  void Teleport(const nav::Pose2& pose);
  // The battery as it is now, and whether the robot stands on the dock's contacts. Thread-safe.
  BatteryState battery_state() const;
  const std::optional<SimDock>& dock() const { return dock_; }
  // Opens or closes a door; false when there is no such door. Thread-safe (takes effect at the next step).
  bool SetDoorOpen(const std::string& id, bool open);
  // Each door's id and whether it is open. Thread-safe.
  std::vector<std::pair<std::string, bool>> doors() const;
  // Sends a lift's car to a floor (its door opens there) or closes its door (floor ""); false for no such lift or
  // floor. Thread-safe (takes effect at the next step).
  bool CallLift(const std::string& id, const std::string& floor);
  // Each lift's state. Thread-safe.
  std::vector<SimLiftState> lifts() const;
  const World& world() const { return *world_; }

  // DepthCamera
  CameraInfo info() const override { return camera_info_; }
  void SetFrameHandler(FrameHandler handler) override { frame_handler_ = std::move(handler); }
  // DiffDriveBase
  BaseLimits limits() const override { return options_.base.limits; }
  void SetVelocity(const nav::Twist2& command) override;
  void SetOdometryHandler(OdometryHandler handler) override { odometry_handler_ = std::move(handler); }
  // Laser2D
  nav::Pose2 base_T_laser() const override {
    return {0.0, 0.0, options_.laser.mount_yaw_deg * std::numbers::pi / 180.0};
  }
  double height_m() const override { return options_.laser.mount_height_m; }
  void SetScanHandler(ScanHandler handler) override { scan_handler_ = std::move(handler); }
  // Battery
  void SetBatteryHandler(BatteryHandler handler) override { battery_handler_ = std::move(handler); }
  // PanServo (the camera's, when sim.camera.pan is enabled)
  PanLimits pan_limits() const override;
  Eigen::Vector2d axis_xy() const override { return {options_.pan.axis_x_m, options_.pan.axis_y_m}; }
  void SetTarget(double pan_rad) override;
  void SetReadingHandler(ReadingHandler handler) override { pan_handler_ = std::move(handler); }
  double pan_rad() const { return pan_rad_.load(); }  // where the camera truly looks. Thread-safe.

 private:
  std::shared_ptr<const World> world_;
  SimOptions options_;
  ManualClock clock_;
  RayCaster caster_;
  RgbdRenderer renderer_;
  std::unique_ptr<SimStereoCamera> stereo_;  // when the camera is a stereo pair
  CameraInfo camera_info_;
  std::mt19937 rng_;

  std::optional<SimDock> dock_;
  mutable std::mutex mutex_;  // guards base_, crowd_, battery_, doors_ and the pending command against other threads
  std::vector<SimDoor> doors_;
  std::vector<SimLift> lifts_;
  bool doors_changed_ = true;       // the collision blocks must be redone (guarded by mutex_)
  bool movers_changed_ = true;      // the casters' moving geometry must be redone (guarded by mutex_)
  void ApplyDoors();                // lock held
  TriangleMesh MoversMesh() const;  // people, closed doors and the lifts' cars; lock held
  // The rotating laser's beams due by `now` cast from the robot at `pose`; a sweep completed goes to the handler.
  void SweepLaser(TimeNs now, const nav::Pose2& pose);
  // The pan servo turned toward its target by one step, its reading handed on when due.
  void StepPan(TimeNs now);
  DiffDriveSim base_;
  Crowd crowd_;
  BatterySim battery_;
  nav::Twist2 pending_command_;
  bool has_pending_command_ = false;

  std::atomic<bool> camera_stopped_{false};
  // The pan servo: its target (any thread), its angle (the stepping thread writes it).
  std::atomic<double> pan_target_rad_{0.0};
  std::atomic<double> pan_rad_{0.0};
  std::atomic<bool> pan_stopped_{false};
  double pan_velocity_rps_ = 0.0;
  ReadingHandler pan_handler_;
  TimeNs next_pan_ns_ = 0;
  std::int64_t step_count_ = 0;
  TimeNs next_odometry_ns_ = 0;
  TimeNs next_frame_ns_ = 0;
  TimeNs next_scan_ns_ = 0;
  bool beams_cast_ = false;  // CastLaserBeam is in use
  // A rotating laser's sweep under way (SimLaserOptions::sweep): its beams so far, when it began.
  std::shared_ptr<LaserScan> sweep_;
  int sweep_done_ = 0;
  TimeNs sweep_start_ns_ = -1;
  TimeNs next_battery_ns_ = 0;
  std::uint64_t frame_sequence_ = 0;
  FrameHandler frame_handler_;
  OdometryHandler odometry_handler_;
  ScanHandler scan_handler_;
  BatteryHandler battery_handler_;
};

}  // namespace corridor::drivers::sim
