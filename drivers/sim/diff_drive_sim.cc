#include "drivers/sim/diff_drive_sim.h"

#include <algorithm>
#include <cmath>

namespace corridor::drivers::sim {
namespace {

double Approach(double current, double target, double max_step) {
  return current + std::clamp(target - current, -max_step, max_step);
}

}  // namespace

DiffDriveSim::DiffDriveSim(const nav::OccupancyGrid& collision, const SimBaseOptions& options, nav::Pose2 start)
    : collision_(collision), options_(options), pose_(start) {}

void DiffDriveSim::Command(const nav::Twist2& command, double now_s) {
  const BaseLimits& l = options_.limits;
  command_.linear_mps = std::clamp(command.linear_mps, -l.max_linear_mps, l.max_linear_mps);
  command_.angular_rps = std::clamp(command.angular_rps, -l.max_angular_rps, l.max_angular_rps);
  command_time_s_ = now_s;
}

void DiffDriveSim::Teleport(const nav::Pose2& pose) {
  pose_ = pose;
  velocity_ = {};
  command_ = {};
}

double Block::Distance(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d local = center.Inverse().Transform(point);
  return (local.cwiseAbs() - half_extents).cwiseMax(0.0).norm();
}

bool DiffDriveSim::Collides(const nav::Pose2& pose) const {
  const double r = options_.limits.footprint_radius_m;
  for (const Block& b : blocks_) {
    if (b.Distance(pose.translation()) < r) return true;
  }
  for (const Disc& d : movers_) {
    if ((d.center - pose.translation()).norm() < r + d.radius_m) return true;
  }
  const double res = collision_.resolution_m();
  const auto centre = collision_.WorldToCell(pose.translation());
  if (!centre) return true;  // off the world
  const int reach = static_cast<int>(std::ceil(r / res)) + 1;
  const Eigen::Vector2d local = collision_.origin().Inverse().Transform(pose.translation()) / res;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const nav::CellIndex c{centre->x + dx, centre->y + dy};
      // The world ends at the grid's edge: cells beyond it count as occupied.
      if (collision_.Contains(c) && collision_.at(c) < nav::kOccupiedCell) continue;
      // Distance from the footprint's centre to the nearest point of the cell, in the grid's frame.
      const double nx = std::clamp(local.x(), static_cast<double>(c.x), c.x + 1.0);
      const double ny = std::clamp(local.y(), static_cast<double>(c.y), c.y + 1.0);
      if (std::hypot(local.x() - nx, local.y() - ny) * res < r) return true;
    }
  }
  return false;
}

void DiffDriveSim::Step(double dt_s, double now_s, std::mt19937& rng) {
  const BaseLimits& l = options_.limits;
  const bool fresh = now_s - command_time_s_ <= options_.command_timeout_s;
  const nav::Twist2 target = fresh ? command_ : nav::Twist2{};
  velocity_.linear_mps = Approach(velocity_.linear_mps, target.linear_mps, l.max_linear_accel_mps2 * dt_s);
  velocity_.angular_rps = Approach(velocity_.angular_rps, target.angular_rps, l.max_angular_accel_rps2 * dt_s);

  nav::Pose2 next = nav::DriveArc(pose_, velocity_, dt_s);
  bumper_ = false;
  if (Collides(next)) {
    // Blocked: the round footprint may still turn in place, but it does not move into the obstacle.
    bumper_ = velocity_.linear_mps != 0.0 || Collides(pose_);
    next = nav::Pose2{pose_.x_m, pose_.y_m, next.yaw_rad};
    velocity_.linear_mps = 0.0;
  }
  // Odometry sees the wheels' real motion with a small multiplicative error, and the systematic ones of wheels
  // configured wrong.
  const nav::Pose2 step = pose_.Inverse() * next;
  std::normal_distribution<double> lin(1.0, options_.odom_linear_noise);
  std::normal_distribution<double> ang(1.0, options_.odom_angular_noise);
  const double fl = lin(rng) * options_.wheel_diameter_error;
  const double fa = ang(rng) * options_.wheel_diameter_error / options_.track_error;
  odom_pose_ = odom_pose_ * nav::Pose2{step.x_m * fl, step.y_m * fl, step.yaw_rad * fa};
  pose_ = next;
}

}  // namespace corridor::drivers::sim
