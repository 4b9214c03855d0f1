// A stereo camera's frames filtered over posed frames before anything reads them (nav/ground/multi_view.h, step 5 of
// ASNS's MMSVF): the driver's frames come in on camera/rgbd_raw, each is placed by the wheel odometry at its time, and
// what is kept goes out on camera/rgbd for MORP or AFDS, the tracker, the 3D map, localization and the console. On the
// control executor, in the camera's control path.
#pragma once

#include <memory>

#include "drivers/depth_camera.h"
#include "nav/ground/multi_view.h"
#include "server/nodes/pose_history.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class MultiViewNode final : public Node {
 public:
  // Throws std::invalid_argument for bad options.
  MultiViewNode(Executor& control, Bus& bus, const nav::PinholeCamera& camera, const nav::MultiViewOptions& options);
  void Activate() override;

 private:
  void OnFrame(const drivers::RgbdFrame& raw);

  nav::MultiViewFilter filter_;
  std::shared_ptr<PoseHistory> odometry_ = std::make_shared<PoseHistory>();  // odom_T_base, filled by a tap
  Topic<drivers::RgbdFrame>& rgbd_topic_ = bus().Get(topics::kRgbd);
};

}  // namespace corridor::server
