// What the native depth cameras' drivers (RealSense through V4L2, OpenNI2) share in their configuration: the depth
// image's size, its intrinsics (a calibration, or the fields of view about the image's centre), where the camera sits
// on the base, and the ranges it measures well.
#pragma once

#include <cmath>
#include <numbers>

#include "nav/geometry/camera_model.h"

namespace corridor::drivers {

struct CameraMountOptions {
  int width = 640;
  int height = 480;
  int fps = 30;
  // From a calibration when fx and fy are positive (cx, cy: the image's centre when not), else from the fields of view.
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double hfov_deg = 58.0;
  double vfov_deg = 45.0;
  double mount_x_m = 0.1;  // the optical centre: forward of the base's centre, above the floor, pitched down
  double mount_height_m = 0.3;
  double tilt_deg = 10.0;
  double min_range_m = 0.2;
  double max_range_m = 6.0;
};

// A size, a rate, and intrinsics: a calibration, or fields of view between 0 and 180 degrees.
inline bool Usable(const CameraMountOptions& o) {
  const bool calibrated = o.fx > 0.0 && o.fy > 0.0;
  const bool seen = o.hfov_deg > 0.0 && o.hfov_deg < 180.0 && o.vfov_deg > 0.0 && o.vfov_deg < 180.0;
  return o.width > 0 && o.height > 0 && o.fps > 0 && (calibrated || seen);
}

inline nav::PinholeCamera ToPinhole(const CameraMountOptions& o) {
  nav::PinholeCamera camera;
  camera.width = o.width;
  camera.height = o.height;
  const double to_rad = std::numbers::pi / 180.0;
  const bool calibrated = o.fx > 0.0 && o.fy > 0.0;
  camera.fx = calibrated ? o.fx : o.width / 2.0 / std::tan(o.hfov_deg * to_rad / 2.0);
  camera.fy = calibrated ? o.fy : o.height / 2.0 / std::tan(o.vfov_deg * to_rad / 2.0);
  camera.cx = calibrated && o.cx > 0.0 ? o.cx : (o.width - 1) / 2.0;
  camera.cy = calibrated && o.cy > 0.0 ? o.cy : (o.height - 1) / 2.0;
  camera.base_T_camera = nav::CameraMount(o.mount_x_m, o.mount_height_m, o.tilt_deg * to_rad);
  return camera;
}

}  // namespace corridor::drivers
