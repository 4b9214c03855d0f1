// Differential-drive kinematics for the simulator: velocity and acceleration limits, a command timeout, a round
// footprint that collides with the world's collision grid (the robot stops and its bumper is pressed, it never
// passes through), and wheel odometry with multiplicative noise.
#pragma once

#include <random>
#include <vector>

#include "drivers/diff_drive_base.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::drivers::sim {

struct SimBaseOptions {
  BaseLimits limits{.max_linear_mps = 0.6,
                    .max_angular_rps = 1.5,
                    .max_linear_accel_mps2 = 1.0,
                    .max_angular_accel_rps2 = 3.0,
                    .footprint_radius_m = 0.2};
  double command_timeout_s = 0.5;    // the base's own watchdog: no command for this long means stop
  double odom_linear_noise = 0.01;   // standard deviation of the distance error, as a fraction of distance
  double odom_angular_noise = 0.02;  // the same for rotation
  // Systematic errors, as a base whose configured wheels are off: the odometry counts with a wheel diameter this many
  // times the true one (its distances and turns that much too long) and a track this many times the true one (its
  // turns that much too short). 1: right. What the wheels' calibration finds.
  double wheel_diameter_error = 1.0;
  double track_error = 1.0;
};

// A rectangle on the floor the robot cannot enter, checked exactly (the dock: grid cells are too coarse to stand
// a centimetre from).
struct Block {
  nav::Pose2 center;
  Eigen::Vector2d half_extents = Eigen::Vector2d::Zero();  // along the centre's x and y axes

  // The nearest distance from `point` to the rectangle (0 inside).
  double Distance(const Eigen::Vector2d& point) const;
};

// A round thing that moves (a person), for collisions.
struct Disc {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
};

// Not thread-safe: the simulator calls it from one thread.
class DiffDriveSim {
 public:
  DiffDriveSim(const nav::OccupancyGrid& collision, const SimBaseOptions& options, nav::Pose2 start);

  // A new command at time now_s; it lapses after command_timeout_s.
  void Command(const nav::Twist2& command, double now_s);
  // Advances by dt_s seconds ending at now_s.
  void Step(double dt_s, double now_s, std::mt19937& rng);
  // Moves the robot (a simulator reset); clears velocity and odometry stays continuous.
  void Teleport(const nav::Pose2& pose);

  // The moving things the robot can bump into, where they are now.
  void SetMovers(std::vector<Disc> movers) { movers_ = std::move(movers); }
  // Solid rectangles besides the grid.
  void SetBlocks(std::vector<Block> blocks) { blocks_ = std::move(blocks); }

  // True when the footprint at `pose` overlaps an occupied cell, a block, a mover, or leaves the grid.
  bool Collides(const nav::Pose2& pose) const;

  const nav::Pose2& pose() const { return pose_; }
  const nav::Pose2& odom_pose() const { return odom_pose_; }
  const nav::Twist2& velocity() const { return velocity_; }
  bool bumper_pressed() const { return bumper_; }

 private:
  const nav::OccupancyGrid& collision_;
  SimBaseOptions options_;
  nav::Pose2 pose_;
  nav::Pose2 odom_pose_;
  nav::Twist2 velocity_;
  nav::Twist2 command_;
  double command_time_s_ = -1e9;
  bool bumper_ = false;
  std::vector<Disc> movers_;
  std::vector<Block> blocks_;
};

}  // namespace corridor::drivers::sim
