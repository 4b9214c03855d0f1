#include "server/nodes/ground_node.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "nav/localization/range_scan.h"
#include "server/runtime/topics.h"

namespace corridor::server {

GroundNode::GroundNode(Executor& control, Bus& bus, const drivers::CameraInfo& camera, const GroundOptions& options,
                       nav::LocalPolicyKind policy)
    : Node("ground", control, bus) {
  if (policy == nav::LocalPolicyKind::kVoxelReactive) {
    voxels_.Reset(camera.camera, [](std::optional<nav::VoxelObstacles>& reader, const nav::PinholeCamera& c) {
      reader.emplace(c, nav::VoxelObstacleOptions{});
    });
    return;
  }
  if (options.test == GroundTest::kAfds) {
    afds_.Reset(camera.camera, [options](std::optional<nav::Afds>& reader, const nav::PinholeCamera& c) {
      reader.emplace(c, options.afds, options.morp);
    });
  } else {
    morp_.Reset(camera.camera, [options](std::optional<nav::Morp>& reader, const nav::PinholeCamera& c) {
      reader.emplace(c, options.morp);
    });
  }
  scan_.Reset(camera.camera, [](std::optional<nav::DepthScan>& reader, const nav::PinholeCamera& c) {
    reader.emplace(c, nav::ForObstacleMemory(nav::DepthScanOptions{}));
  });
}

GroundNode::GroundNode(Executor& control, Bus& bus, const nav::Pose2& base_T_laser, double height_m,
                       const nav::MorpOptions& options)
    : Node("ground", control, bus), base_T_laser_(base_T_laser), max_range_m_(options.max_range_m) {
  laser_lanes_.emplace(options, height_m);
}

GroundLanes GroundNode::Process(const drivers::RgbdFrame& frame) {
  GroundLanes out{frame.stamp_ns, frame.arrival_ns, frame.sequence, 0.0, {}, {}, {}, {}};
  const std::optional<Eigen::Isometry3d>& pose = frame.base_T_camera;
  if (voxels_) {
    out.obstacles = voxels_.At(pose).Process(frame.depth_mm);
  } else {
    out.lanes = afds_ ? afds_.At(pose).Process(frame.depth_mm).lanes : morp_.At(pose).Process(frame.depth_mm);
    out.scan = scan_.At(pose).Process(frame.depth_mm);
    out.scan_view = scan_->View(nav::Pose2{});
  }
  return out;
}

GroundLanes GroundNode::Process(const drivers::LaserScan& scan) {
  // Taken up at once on the control executor: its arrival is now (the gate's patience is the laser's).
  GroundLanes out{scan.stamp_ns, clock().Now(), ++laser_sequence_, 0.0, {}, {}, {}, {}};
  nav::RangeLimits limits;
  limits.min_range_m = std::max(scan.range_min_m, 0.01);
  limits.max_range_m = scan.range_max_m > 0.0 ? scan.range_max_m : limits.max_range_m;
  const nav::RangeScan hits =
      nav::ScanFromRanges(base_T_laser_, scan.angle_min_rad, scan.angle_increment_rad, scan.ranges, limits);
  out.lanes = laser_lanes_->Process(hits.hits);
  for (const Eigen::Vector2f& p : hits.hits) {
    if ((p - hits.origin).norm() <= max_range_m_) out.scan.push_back(p.cast<double>());
  }
  // What the scan covers: all around for a full sweep, else its span's narrower side of straight ahead.
  const double last_rad = scan.angle_min_rad + scan.angle_increment_rad * static_cast<double>(scan.ranges.size());
  const double half_rad = std::abs(last_rad - scan.angle_min_rad) >= 2.0 * std::numbers::pi - 1e-3
                              ? std::numbers::pi
                              : std::min(std::abs(scan.angle_min_rad), std::abs(last_rad));
  out.scan_view = nav::SensorView{base_T_laser_, half_rad, std::min(limits.max_range_m, max_range_m_)};
  return out;
}

void GroundNode::Activate() {
  auto& lanes = ground_lanes_topic_;
  // The front end's own time is wall time from the moment the control executor takes the frame (or scan) up to the
  // lanes being ready (the loop "frame" times it too).
  const auto publish = [&lanes](GroundLanes out, std::chrono::steady_clock::time_point start) {
    out.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    lanes.Publish(std::move(out));
  };
  if (laser_lanes_) {
    Subscribe(topics::kScan, "frame", [this, publish](const std::shared_ptr<const drivers::LaserScan>& scan) {
      const auto start = std::chrono::steady_clock::now();
      publish(Process(*scan), start);
    });
    SetHealth(Health::kOk, std::to_string(laser_lanes_->lane_count()) + " lanes from the laser");
    return;
  }
  Subscribe(topics::kRgbd, "frame", [this, publish](const std::shared_ptr<const drivers::RgbdFrame>& frame) {
    const auto start = std::chrono::steady_clock::now();
    publish(Process(*frame), start);
  });
  SetHealth(Health::kOk, voxels_ ? "voxel grid front end"
                         : afds_ ? std::to_string(afds_->lane_count()) + " lanes (AFDS)"
                                 : std::to_string(morp_->lane_count()) + " lanes");
}

}  // namespace corridor::server
