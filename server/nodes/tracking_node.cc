#include "server/nodes/tracking_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {

namespace {

constexpr double kTrafficEveryS = 1.0;  // how often the planner gets new traffic costs

}  // namespace

TrackingNode::TrackingNode(Executor& mapping, Bus& bus, const drivers::Clock& clock, const nav::Pose2& base_T_laser,
                           const nav::MovingObjectOptions& options, const nav::TrafficOptions& traffic,
                           TrafficCallback on_traffic)
    : Node("tracking", mapping.name(), clock), executor_(mapping), bus_(bus), base_T_laser_(base_T_laser),
      tracker_(options), traffic_options_(traffic), on_traffic_(std::move(on_traffic)) {}

void TrackingNode::Activate() {
  bus_.Get(topics::kScan).Subscribe(executor_, [this](const std::shared_ptr<const drivers::LaserScan>& scan) {
    OnScan(*scan);
  });
  SetHealth(Health::kOk, "waiting for scans");
}

void TrackingNode::SetMap(std::shared_ptr<const nav::OccupancyGrid> map) {
  executor_.Post([this, map = std::move(map)]() mutable {
    traffic_.reset();
    if (map && traffic_options_.weight > 0.0 && on_traffic_) traffic_.emplace(*map, traffic_options_);
    map_ = map;
    tracker_.SetMap(std::move(map));
  });
}

void TrackingNode::OnScan(const drivers::LaserScan& scan) {
  const drivers::TimeNs start = clock().Now();
  const auto pose = bus_.Get(topics::kPose).latest();
  if (!pose) {
    SetHealth(Health::kDegraded, "no pose yet: scans cannot be placed in the map");
    return;
  }
  const nav::Pose2 laser = pose->pose * base_T_laser_;
  tracker_.Update(drivers::ToSeconds(scan.stamp_ns), laser.translation(),
                  nav::ScanToWorld(laser, scan.angle_min_rad, scan.angle_increment_rad, scan.range_min_m,
                                   scan.range_max_m, scan.ranges));
  const double stamp_s = drivers::ToSeconds(scan.stamp_ns);
  if (traffic_) {
    traffic_->Add(stamp_s, tracker_.objects());
    if (stamp_s - traffic_sent_s_ >= kTrafficEveryS || stamp_s < traffic_sent_s_) {
      traffic_sent_s_ = stamp_s;
      // Nobody walking (or long gone): no costs, and missions keep their paths.
      on_traffic_(traffic_->Empty(stamp_s) ? nullptr
                                           : std::make_shared<const std::vector<float>>(traffic_->StepCost(stamp_s)),
                  map_.get());
    }
  }
  stats().Record(start);
  std::size_t moving = 0;
  for (const nav::TrackedObject& o : tracker_.objects()) moving += o.moving ? 1 : 0;
  SetHealth(Health::kOk, std::to_string(tracker_.objects().size()) + " objects, " + std::to_string(moving) + " moving");
  bus_.Get(topics::kTrackedObjects).Publish(TrackedObjects{scan.stamp_ns, clock().Now(), tracker_.surroundings()});
}

}  // namespace corridor::server
