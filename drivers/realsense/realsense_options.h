// What the configuration holds for a RealSense D4xx through V4L2 (realsense_camera.h), without the driver itself.
#pragma once

#include <string>

#include "drivers/camera_mount.h"

namespace corridor::drivers::realsense {

struct RealSenseOptions {
  // The V4L2 nodes: found among /dev/video* by this part of the device's name (the kernel's uvcvideo names a D435's
  // "Intel(R) RealSense(TM) Depth Camera 435 ..."), the depth node the one that offers Z16, the colour node the one
  // that offers YUYV and not Z16; or given as paths.
  std::string name = "RealSense";
  std::string depth_node;
  std::string color_node;  // "none": no colour (frames are black)
  // The depth's size, rate, intrinsics and mounting (the colour is scaled to its size). A D435's depth sees 87 x 58
  // degrees.
  CameraMountOptions camera{640, 480, 30, 0.0, 0.0, 0.0, 0.0, 87.0, 58.0};
  double depth_scale_m = 0.001;  // metres a Z16 unit (a D4xx's default depth unit, 1 mm)
  double stale_s = 0.08;         // no depth frame for this long: the link is stale
  double silence_s = 1.0;        // no frame for this long: the nodes are opened anew
  double reconnect_s = 1.0;
};

}  // namespace corridor::drivers::realsense
