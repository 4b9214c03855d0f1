// The front end of the control path, on the control executor, published on ground/lanes with its own time; the local
// policy and the command gate read them. On every depth frame: MORP ground segmentation (nav/ground/morp.h), or
// ASNS's floor detection (nav/ground/afds.h) in its place, and the frame's depth scan for the obstacle memory, or, for
// the voxel-reactive comparison policy, the voxel grid's obstacle points (nav/ground/voxel_obstacles.h). On a robot
// without a camera, on every laser scan: the same lanes from the scan's hits (nav/ground/laser_lanes.h), and the hits
// for the obstacle memory. A frame from a camera turned on a pan servo is read with the camera's pose at the frame
// (the lanes are the robot's, straight ahead; those the camera does not see have no evidence).
#pragma once

#include <cstdint>
#include <optional>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "nav/geometry/posed.h"
#include "nav/ground/afds.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/laser_lanes.h"
#include "nav/ground/morp.h"
#include "nav/ground/voxel_obstacles.h"
#include "nav/policy/local_policy.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class GroundNode final : public Node {
 public:
  // From the depth camera's frames, with the ground test `options` choose.
  GroundNode(Executor& control, Bus& bus, const drivers::CameraInfo& camera, const GroundOptions& options,
             nav::LocalPolicyKind policy = nav::LocalPolicyKind::kMorpRb);
  // From the laser's scans (no camera): the laser at `base_T_laser`, `height_m` above the floor.
  GroundNode(Executor& control, Bus& bus, const nav::Pose2& base_T_laser, double height_m,
             const nav::MorpOptions& options);
  void Activate() override;

 private:
  GroundLanes Process(const drivers::RgbdFrame& frame);
  GroundLanes Process(const drivers::LaserScan& scan);

  // From the camera (each following its pose, for a camera on a pan servo):
  nav::Posed<nav::Morp> morp_;
  nav::Posed<nav::Afds> afds_;              // AFDS in MORP's place (ground.test: afds)
  nav::Posed<nav::DepthScan> scan_;         // for the obstacle memory (nav::ForObstacleMemory)
  nav::Posed<nav::VoxelObstacles> voxels_;  // voxel-reactive's front end instead of MORP
  // From the laser:
  std::optional<nav::LaserLanes> laser_lanes_;
  nav::Pose2 base_T_laser_;
  double max_range_m_ = 0.0;  // the lanes' (options.max_range_m)
  std::uint64_t laser_sequence_ = 0;

  // The topics it reads and writes, resolved once.
  Topic<GroundLanes>& ground_lanes_topic_ = bus().Get(topics::kGroundLanes);
};

}  // namespace corridor::server
