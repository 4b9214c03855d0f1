// The depth front end of the control path, on every depth frame, on the control executor: MORP ground segmentation
// (nav/ground/morp.h) and the frame's depth scan for the obstacle memory, or, for the voxel-reactive comparison policy,
// the voxel grid's obstacle points (nav/ground/voxel_obstacles.h). Published on ground/lanes with the front end's own
// time; the local policy and the command gate read them.
#pragma once

#include "drivers/depth_camera.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/morp.h"
#include "nav/ground/voxel_obstacles.h"
#include "nav/policy/local_policy.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class GroundNode final : public Node {
 public:
  GroundNode(Executor& control, Bus& bus, const drivers::CameraInfo& camera, const nav::MorpOptions& options,
             nav::LocalPolicyKind policy = nav::LocalPolicyKind::kMorpRb);
  void Activate() override;

 private:
  GroundLanes Process(const drivers::RgbdFrame& frame);

  nav::Morp morp_;
  nav::DepthScan scan_;  // for the obstacle memory (nav::ForObstacleMemory)
  std::optional<nav::VoxelObstacles> voxels_;  // voxel-reactive's front end instead of MORP
};

}  // namespace corridor::server
