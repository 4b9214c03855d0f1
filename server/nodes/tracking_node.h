// Tracks moving objects (nav/tracking/moving_objects.h) from the 2D laser, or, on a robot without one, from the depth
// camera's frames turned into scans (nav/ground/depth_scan.h: people are followed within the camera's view). Each
// scan is put in the map frame with the newest pose estimate and added to the tracker, whose objects and static
// points go out on tracking/objects for the mission's evasion and the console. On the mapping executor, off the
// camera's control path. Walls of the map in use (topics::kMapInUse) are not objects. The tracks also mark where
// people walk (nav/tracking/traffic_map.h); every second the costs of those ways go to the planner
// (topics::kTrafficLayer), unless traffic.weight is 0.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"
#include "nav/geometry/posed.h"
#include "nav/ground/depth_scan.h"
#include "nav/map/occupancy_grid.h"
#include "nav/tracking/moving_objects.h"
#include "nav/tracking/traffic_map.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

// What the tracker reads: the laser's scans when there is a laser, else the depth camera's frames.
struct TrackingSource {
  std::optional<nav::Pose2> base_T_laser;  // the laser's pose on the robot; none: no laser
  nav::PinholeCamera camera;               // used without a laser
  nav::DepthScanOptions depth;
};

class TrackingNode final : public Node {
 public:
  // Throws std::invalid_argument for bad options (or, without a laser, a camera without size or focal length).
  TrackingNode(Executor& mapping, Bus& bus, const TrackingSource& source, const nav::MovingObjectOptions& options,
               const nav::TrafficOptions& traffic);
  void Activate() override;

 private:
  // The newest pose estimate; none before the first, and the node says that `what` cannot be placed.
  std::optional<nav::Pose2> RobotPose(const char* what);
  void OnScan(const drivers::LaserScan& scan);
  void OnFrame(const drivers::RgbdFrame& frame);
  // A new map in use: its walls for the tracker, and where people walk starts again over it.
  void OnMap(const MapInUse& map);
  // Adds one scan, taken at stamp_ns from `sensor` (map frame; `view`: what it covers when not all round), its points
  // already in the map frame; hands on the traffic costs when due and publishes the objects.
  void Track(drivers::TimeNs stamp_ns, const Eigen::Vector2d& sensor, const std::vector<Eigen::Vector2d>& points,
             const std::optional<nav::SensorView>& view);

  TrackingSource source_;
  nav::Posed<nav::DepthScan> depth_scan_;  // without a laser (following the camera's pose)
  nav::MovingObjectTracker tracker_;
  nav::TrafficOptions traffic_options_;
  std::optional<nav::TrafficMap> traffic_;                            // over the current map
  std::shared_ptr<const nav::OccupancyGrid> map_;                     // the current map
  double traffic_sent_s_ = -std::numeric_limits<double>::infinity();  // scan time of the last costs handed on

  // The topics it reads and writes, resolved once.
  Topic<StampedPose>& pose_topic_ = bus().Get(topics::kPose);
  Topic<TrackedObjects>& tracked_objects_topic_ = bus().Get(topics::kTrackedObjects);
  Topic<TrafficLayer>& traffic_topic_ = bus().Get(topics::kTrafficLayer);
};

}  // namespace corridor::server
