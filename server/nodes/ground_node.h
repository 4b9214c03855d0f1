// Runs MORP ground segmentation (nav/ground/morp.h) on every depth frame, on the control executor, and publishes the
// lanes on ground/lanes with the time from the frame's arrival, and the frame's depth scan for the obstacle memory.
// The local policy and the command gate read them.
#pragma once

#include "drivers/depth_camera.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/morp.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class GroundNode final : public Node {
 public:
  GroundNode(Executor& control, Bus& bus, const drivers::CameraInfo& camera, const nav::MorpOptions& options);
  void Activate() override;

 private:
  nav::Morp morp_;
  nav::DepthScan scan_;  // for the obstacle memory (nav::ForObstacleMemory)
};

}  // namespace corridor::server
