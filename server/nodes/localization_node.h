// Where the robot is in the map, on the pose topic at the odometry's rate: map_T_odom * odom_T_base, made from each
// odometry reading on its publisher's thread (a tap: the node's thread wakes for scans, not for the odometry's 50 Hz),
// with map_T_odom from one of three sources (localization.source):
//   - mcl: Monte Carlo localization in the active map (nav/localization/monte_carlo.h) from the laser's scans or,
//     without a laser, from each depth frame's scan (nav/ground/depth_scan.h). Each scan updates the filter with the
//     odometry at the scan's time; map_T_odom follows. When the filter is lost, a global search of the map runs every
//     relocalize_every_s until it finds the robot again; the camera's narrow view searches with the scans of its last
//     turn or few metres joined by odometry (nav/localization/scan_history.h). Its state (pose, covariance, health,
//     particles) is on the localization topic; commands (set a pose, relocalize) arrive on localization/command.
//     Mapping (a command too) replaces the filter with graph SLAM (nav/localization/graph_slam.h) started where the
//     robot is, so the new map lines up with the old one; the map as built so far is on the mapping topic. Stopping
//     renders the map and hands it to on_map_built (the map library saves it and makes it the map in use, which
//     comes back on topics::kMapInUse): localization then goes on in it.
//   - odometry: dead reckoning from the configured start (it drifts);
//   - sim_truth: the simulator's ground truth.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>

#include "nav/geometry/posed.h"
#include "nav/ground/depth_scan.h"
#include "nav/localization/graph_slam.h"
#include "nav/localization/monte_carlo.h"
#include "nav/localization/scan_history.h"
#include "server/config/config.h"
#include "server/nodes/odometry_frame.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"
#include "server/store/saved_pose.h"

namespace corridor::server {

// What localization made of a pose it was given (LocalizationNode::SetPose).
struct PoseCheck {
  bool taken = false;             // false: not now (mapping under way); `detail` says why
  bool checked = false;           // the last scan was held against the map at the pose (mcl with a scan so far)
  double agreement = 0.0;         // the fraction of that scan on the map's walls at the given pose
  double agreement_before = 0.0;  // and at the pose localization had
  bool agrees = true;             // the scan fits the map at the given pose (or it could not be checked)
  std::string detail;             // for people
};

class LocalizationNode final : public Node {
 public:
  // Saves a map just built under `name` and makes it the active one; throws std::exception (with why) if it cannot.
  using MapBuilt = std::function<void(const std::string& name, nav::OccupancyGrid grid)>;

  // base_T_laser: where the laser is, or nullopt without one (mcl then reads the depth camera, `camera`).
  // pose_file: where the pose is saved whenever it moved 0.1 m or 5 degrees (and not while lost); empty: nowhere.
  // restored: the pose saved before a restart; used instead of initial_pose when the first map set is its map (if
  // the scans disagree with that map there, the filter is soon lost and searches the map).
  LocalizationNode(Executor& executor, Bus& bus, const LocalizationOptions& options, nav::Pose2 initial_pose,
                   std::optional<nav::Pose2> base_T_laser, const nav::PinholeCamera& camera,
                   std::filesystem::path pose_file = {}, std::optional<SavedPose> restored = std::nullopt,
                   MapBuilt on_map_built = {});
  void Activate() override;
  // Saves the last estimate, however little the robot moved since the last save (the node's executor has stopped).
  void Cleanup() override;
  // Takes `pose` (map frame) with its spread, as the localization/command kSetPose does, and answers with how well the
  // last scan fits the map there against where localization had the robot: a pose the sensors contradict is taken,
  // but the caller is told that the filter will likely move away from it. Thread-safe: applied on the node's executor,
  // where `done` is called, once.
  void SetPose(const nav::Pose2& pose, double sigma_m, double sigma_rad, std::function<void(PoseCheck)> done);

 private:
  void OnScan(const drivers::LaserScan& scan);
  void OnFrame(const drivers::RgbdFrame& frame);
  // One scan (base frame) taken at stamp_ns: the filter's update, a search when one is due, the pose published.
  void Localize(drivers::TimeNs stamp_ns, const nav::RangeScan& scan);
  void OnCommand(const LocalizationCommand& command);
  // The map to localize in (mcl), when another (or the same with its cells edited) is in use: the filter restarts
  // around the last estimate.
  void OnMap(const MapInUse& map);
  PoseCheck TakePose(const nav::Pose2& pose, double sigma_m, double sigma_rad);
  void Publish(drivers::TimeNs stamp_ns);
  void ResetFilter(const nav::Pose2& pose, double sigma_m, double sigma_rad);
  // Writes the pose to pose_file_ when it moved enough since the last write (always with `always`). Throws when the
  // file cannot be written.
  void Save(const nav::Pose2& pose, double sigma_m, double sigma_rad, bool always = false);
  void StartMapping(const std::string& name);
  void StopMapping();
  // One scan into the map being built.
  void Map(drivers::TimeNs stamp_ns, const nav::Pose2& odom, const nav::RangeScan& scan);
  void PublishMapping(drivers::TimeNs stamp_ns, bool render);

  LocalizationOptions options_;
  std::optional<nav::Pose2> base_T_laser_;
  nav::Posed<nav::DepthScan> depth_scan_;  // without a laser (following the camera's pose)
  nav::ScanHistory history_;               // what the camera saw lately, for a search (no laser)
  double look_around_rps_ = 0.0;           // lost with the camera's narrow view: turn on the spot to see more
  // The odometry's last second and map_T_odom, shared with the odometry's tap.
  std::shared_ptr<OdometryFrame> frame_;
  bool tapped_ = false;  // the odometry's tap is in place (a topic keeps its taps)
  bool held_ = false;    // on odometry alone, the scans not weighed (riding a lift)
  std::shared_ptr<const nav::OccupancyGrid> map_;
  std::string map_name_;
  std::filesystem::path pose_file_;
  std::optional<SavedPose> saved_;     // what the file holds
  std::optional<SavedPose> restored_;  // until the first map is set
  std::unique_ptr<nav::MonteCarloLocalization> filter_;
  bool relocalize_ = false;                                         // search the whole map on the next scan
  std::optional<std::pair<nav::Pose2, nav::RangeScan>> last_scan_;  // the last one localized with, and its odometry
  drivers::TimeNs last_search_ns_ = 0;
  MapBuilt on_map_built_;
  std::unique_ptr<nav::GraphSlam> slam_;  // while mapping
  nav::Pose2 slam_odom_;                  // the odometry of the last scan mapped
  MappingState mapping_;                  // as last published
  drivers::TimeNs last_render_ns_ = 0;

  // The topics it reads and writes, resolved once.
  Topic<LocalizationState>& localization_topic_ = bus().Get(topics::kLocalization);
  Topic<MappingState>& mapping_topic_ = bus().Get(topics::kMapping);
  Topic<StampedPose>& pose_topic_ = bus().Get(topics::kPose);
};

}  // namespace corridor::server
