#include "server/nodes/tracking_node.h"

#include <optional>
#include <stdexcept>
#include <string>

#include "server/runtime/topics.h"

namespace corridor::server {

namespace {

constexpr double kTrafficEveryS = 1.0;  // how often the planner gets new traffic costs

}  // namespace

TrackingNode::TrackingNode(Executor& mapping, Bus& bus, const TrackingSource& source,
                           const nav::MovingObjectOptions& options, const nav::TrafficOptions& traffic)
    : Node("tracking", mapping, bus),
      source_(source),
      tracker_(source.base_T_laser ? options : nav::ForDepthCamera(options)),
      traffic_options_(traffic) {
  if (!source.base_T_laser) {
    depth_scan_.Reset(source.camera,
                      [depth = source.depth](std::optional<nav::DepthScan>& scan, const nav::PinholeCamera& camera) {
                        scan.emplace(camera, depth);
                      });
  }
}

void TrackingNode::Activate() {
  Subscribe(topics::kMapInUse, "map", [this](const auto& map) { OnMap(*map); });
  if (source_.base_T_laser) {
    Subscribe(topics::kScan, "scan", [this](const auto& scan) { OnScan(*scan); });
    SetHealth(Health::kOk, "waiting for scans");
  } else {
    Subscribe(topics::kRgbd, "frame", [this](const auto& frame) { OnFrame(*frame); });
    SetHealth(Health::kOk, "waiting for depth frames (no laser: people are tracked in the camera's view)");
  }
}

void TrackingNode::OnMap(const MapInUse& map) {
  if (!map.grid || map.grid == map_) return;  // its zones or doors changed, not its walls
  traffic_.reset();
  if (map.grid && traffic_options_.weight > 0.0) traffic_.emplace(*map.grid, traffic_options_);
  map_ = map.grid;
  tracker_.SetMap(map.grid);
}

std::optional<nav::Pose2> TrackingNode::RobotPose(const char* what) {
  const auto pose = pose_topic_.latest();
  if (!pose) {
    SetHealth(Health::kDegraded, std::string("no pose yet: ") + what + " cannot be placed in the map");
    return std::nullopt;
  }
  return pose->pose;
}

void TrackingNode::OnScan(const drivers::LaserScan& scan) {
  const std::optional<nav::Pose2> robot = RobotPose("scans");
  if (!robot) return;
  const nav::Pose2 laser = *robot * *source_.base_T_laser;
  Track(scan.stamp_ns, laser.translation(),
        nav::ScanToWorld(laser, scan.angle_min_rad, scan.angle_increment_rad, scan.range_min_m, scan.range_max_m,
                         scan.ranges),
        std::nullopt);
}

void TrackingNode::OnFrame(const drivers::RgbdFrame& frame) {
  const std::optional<nav::Pose2> robot = RobotPose("depth frames");
  if (!robot) return;
  std::vector<Eigen::Vector2d> points;
  try {
    for (const Eigen::Vector2d& p : depth_scan_.At(frame.base_T_camera).Process(frame.depth_mm)) {
      points.push_back(robot->Transform(p));
    }
  } catch (const std::invalid_argument& e) {
    SetHealth(Health::kDegraded, e.what());
    return;
  }
  const nav::SensorView view = depth_scan_->View(*robot);
  Track(frame.stamp_ns, view.world_T_sensor.translation(), points, view);
}

void TrackingNode::Track(drivers::TimeNs stamp_ns, const Eigen::Vector2d& sensor,
                         const std::vector<Eigen::Vector2d>& points, const std::optional<nav::SensorView>& view) {
  tracker_.Update(drivers::ToSeconds(stamp_ns), sensor, points, view);
  const double stamp_s = drivers::ToSeconds(stamp_ns);
  if (traffic_) {
    traffic_->Add(stamp_s, tracker_.objects());
    if (stamp_s - traffic_sent_s_ >= kTrafficEveryS || stamp_s < traffic_sent_s_) {
      traffic_sent_s_ = stamp_s;
      // Nobody walking (or long gone): no costs, and missions keep their paths.
      traffic_topic_.Publish(TrafficLayer{
          map_, traffic_->Empty(stamp_s) ? nullptr
                                         : std::make_shared<const std::vector<float>>(traffic_->StepCost(stamp_s))});
    }
  }
  std::size_t moving = 0;
  for (const nav::TrackedObject& o : tracker_.objects()) moving += o.moving ? 1 : 0;
  SetHealth(Health::kOk, std::to_string(tracker_.objects().size()) + " objects, " + std::to_string(moving) + " moving");
  tracked_objects_topic_.Publish(TrackedObjects{stamp_ns, clock().Now(), tracker_.surroundings()});
}

}  // namespace corridor::server
