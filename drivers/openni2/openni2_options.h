// What the configuration holds for an OpenNI2 depth camera (openni2_camera.h), without the driver itself.
#pragma once

#include <string>

#include "drivers/camera_mount.h"

namespace corridor::drivers::openni2 {

struct OpenNi2Options {
  std::string uri;    // the device's URI (OpenNI2's own, as the console's Devices page lists them); empty: the first
  bool color = true;  // stream colour too, registered to the depth where the device can
  // The depth's size, rate, intrinsics and mounting. An Astra's or an Xtion's depth sees about 58 x 45 degrees.
  CameraMountOptions camera;
  double stale_s = 0.08;   // no depth frame for this long: the link is stale
  double silence_s = 1.0;  // no frame for this long: the device is opened anew
  double reconnect_s = 1.0;
};

}  // namespace corridor::drivers::openni2
