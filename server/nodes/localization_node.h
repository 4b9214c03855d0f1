// Where the robot is in the map, on the pose topic at the odometry's rate: map_T_odom * odom_T_base, with map_T_odom
// from one of three sources (localization.source):
//   - mcl: Monte Carlo localization in the active map from the laser's scans (nav/localization/monte_carlo.h). Each
//     scan updates the filter with the odometry at the scan's time; map_T_odom follows. When the filter is lost, a
//     global search of the map runs every relocalize_every_s until it finds the robot again. Its state (pose,
//     covariance, health, particles) is on the localization topic; commands (set a pose, relocalize) arrive on
//     localization/command.
//   - odometry: dead reckoning from the configured start (it drifts);
//   - sim_truth: the simulator's ground truth.
#pragma once

#include <deque>
#include <memory>
#include <optional>

#include "nav/localization/monte_carlo.h"
#include "server/runtime/bus.h"
#include "server/runtime/config.h"
#include "server/runtime/node.h"
#include "server/store/saved_pose.h"

namespace corridor::server {

class LocalizationNode final : public Node {
 public:
  // base_T_laser: where the laser is, or nullopt without one (mcl then falls back to odometry, degraded).
  // pose_file: where the pose is saved whenever it moved 0.1 m or 5 degrees (and not while lost); empty: nowhere.
  // restored: the pose saved before a restart; used instead of initial_pose when the first map set is its map (if
  // the scans disagree with that map there, the filter is soon lost and searches the map).
  LocalizationNode(Executor& executor, Bus& bus, const LocalizationOptions& options, nav::Pose2 initial_pose,
                   std::optional<nav::Pose2> base_T_laser, std::filesystem::path pose_file = {},
                   std::optional<SavedPose> restored = std::nullopt);
  void Activate() override;
  // The map to localize in (mcl), by name. Thread-safe: applied on the node's executor. A new map keeps the pose if
  // it lies on the map; the filter restarts around it.
  void SetMap(std::string name, std::shared_ptr<const nav::OccupancyGrid> map);

 private:
  void OnOdometry(const drivers::WheelOdometry& odometry);
  void OnScan(const drivers::LaserScan& scan);
  void OnCommand(const LocalizationCommand& command);
  // The odometry at `stamp_ns`, interpolated between the readings around it; nullopt before any.
  std::optional<nav::Pose2> OdometryAt(drivers::TimeNs stamp_ns) const;
  // The last odometry reading; the identity before any.
  nav::Pose2 LatestOdometry() const;
  void Publish(drivers::TimeNs stamp_ns);
  void ResetFilter(const nav::Pose2& pose, double sigma_m, double sigma_rad);
  void Save(const nav::Pose2& pose, double sigma_m, double sigma_rad);

  LocalizationOptions options_;
  std::optional<nav::Pose2> base_T_laser_;
  nav::Pose2 map_T_odom_;
  std::shared_ptr<const nav::OccupancyGrid> map_;
  std::string map_name_;
  std::filesystem::path pose_file_;
  std::optional<SavedPose> saved_;     // what the file holds
  std::optional<SavedPose> restored_;  // until the first map is set
  std::unique_ptr<nav::MonteCarloLocalization> filter_;
  std::deque<drivers::WheelOdometry> odometry_;  // the last second
  bool relocalize_ = false;                      // search the whole map on the next scan
  drivers::TimeNs last_search_ns_ = 0;
};

}  // namespace corridor::server
