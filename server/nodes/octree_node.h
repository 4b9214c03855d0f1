// The 3D map of the map in use (nav/mapping/occupancy_octree.h), on the mapping executor. A depth frame goes in
// every insert_every_s at the robot's pose at the frame's time, while the pose is trusted: localization ok (or its
// source is not the filter), or the map being built. What stands between min_height_m and max_height_m (the step
// height and the robot's height) goes to the planner as a costmap layer (topics::kObstacleLayer), when it changed,
// every update_every_s:
// only the neighbourhood of the frames inserted since is projected again (the octree of a whole building is large).
// The API's snapshot is taken when asked for, at most every update_every_s.
//
// Each map has its own octree, <maps_dir>/NAME/map.bt (OctoMap binary), read when the map becomes active and
// written every save_every_s while it changes, when another map becomes active and at shutdown. Mapping a new
// building starts an empty octree under the new name; it is written once the map is saved (and active).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nav/mapping/occupancy_octree.h"
#include "server/config/config.h"
#include "server/nodes/pose_history.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

// What the API serves of the 3D map.
struct OctreeSnapshot {
  std::string map;             // whose octree
  std::uint64_t revision = 0;  // of the octree: bumped by every change
  double resolution_m = 0.0;
  std::size_t leaves = 0;
  std::string bt;             // OctoMap binary
  std::vector<float> voxels;  // occupied leaves, x y z size each (map frame)
};

class OctreeNode final : public Node {
 public:
  OctreeNode(Executor& mapping, Bus& bus, const OctreeOptions& options, const nav::PinholeCamera& camera,
             bool trust_pose, std::filesystem::path maps_dir);
  void Activate() override;
  void Cleanup() override;  // saves: the executors have stopped, nothing else touches the octree
  // Calls `done` on the node's executor with a snapshot of the octree (taken again if it changed and the last is
  // older than update_every_s), or null before the first map. Thread-safe.
  void Snapshot(std::function<void(std::shared_ptr<const OctreeSnapshot>)> done);
  // Where a map's octree is kept.
  std::filesystem::path FileOf(const std::string& map) const { return maps_dir_ / map / "map.bt"; }

 private:
  void OnFrame(const drivers::RgbdFrame& frame);
  void OnMapping(const MappingState& mapping);
  // Another map in use (or the same one with its cells edited): its octree, and its layer again from the start.
  void OnMap(const MapInUse& map);
  // The robot's pose at stamp_ns, between the poses published around it; nullopt when none is near.
  std::optional<nav::Pose2> PoseAt(drivers::TimeNs stamp_ns) const;
  bool PoseTrusted();
  // Switches to `name`'s octree: the current one saved first, the new one read from its file (or empty).
  void Switch(const std::string& name);
  void Save();
  // The layer for the planner, again where frames went in since the last.
  void UpdateLayer();
  // The region a frame taken from map_T_base may have changed.
  void Touched(const nav::Pose2& map_T_base);

  OctreeOptions options_;
  nav::PinholeCamera camera_;
  bool trust_pose_;  // the pose is not the filter's (odometry or the simulator's truth)
  std::filesystem::path maps_dir_;
  nav::OccupancyOctree octree_;
  std::string name_;                               // whose octree octree_ is
  std::shared_ptr<const nav::OccupancyGrid> map_;  // the active map's grid (the layer's geometry)
  bool mapping_ = false;                           // a new map is being built under name_
  std::uint64_t revision_ = 0;                     // bumped by every change of the octree
  bool unsaved_ = false;                           // changed since the last save
  std::optional<Eigen::AlignedBox2d> touched_;     // where it changed since the layer was last projected
  std::shared_ptr<PoseHistory> poses_ = std::make_shared<PoseHistory>();  // the last second, filled by a tap
  bool tapped_ = false;
  drivers::TimeNs last_insert_ns_ = 0;
  drivers::TimeNs last_update_ns_ = 0;
  drivers::TimeNs last_save_ns_ = 0;
  std::shared_ptr<const std::vector<std::int8_t>> layer_;
  std::shared_ptr<const OctreeSnapshot> snapshot_;
  drivers::TimeNs snapshot_ns_ = 0;
  Topic<ObstacleLayer>& obstacle_topic_ = bus().Get(topics::kObstacleLayer);
};

}  // namespace corridor::server
