// What the configuration holds for a stereo camera (stereo_camera.h), without the driver itself.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "drivers/stereo/multi_baseline.h"
#include "drivers/stereo/stereo_calibration.h"
#include "drivers/stereo/stereo_depth.h"
#include "drivers/stereo/stereo_frames.h"

namespace corridor::drivers::stereo {

enum class StereoLayout {
  kSideBySide,  // one UVC device whose frames hold both views (the left camera's in the left half)
  kTwoCameras,  // two UVC cameras, paired by their frames' time stamps
};

struct StereoCameraOptions {
  StereoLayout layout = StereoLayout::kSideBySide;
  // Side by side: the V4L2 node, or found among /dev/video* by this part of the device's name. Two cameras: both nodes
  // (stable names such as /dev/v4l/by-path/...: two cameras of one model share their name).
  std::string name = "Stereo";
  std::string node;
  std::string left_node, right_node;
  VideoFormat format = VideoFormat::kMjpeg;
  int width = 640;  // one view's size (a side-by-side frame is twice as wide)
  int height = 480;
  int fps = 30;
  std::filesystem::path calibration_file;  // corridor-stereo calibrate's output
  StereoCalibration calibration;           // read from it by the configuration
  // ASNS's wide baseline: a third camera beyond the right one (its node, paired by time stamps with the others) and
  // the calibration of the left camera with it; the two pairs are fused (MultiBaselineDepth). Empty: a pair only.
  std::string third_node;
  std::filesystem::path wide_calibration_file;
  std::optional<StereoCalibration> wide_calibration;
  int wide_disparities = 64;
  BaselineFusionOptions fusion;
  double mount_x_m = 0.1;  // the left camera's optical centre: forward of the base's centre, above the floor, pitched
  double mount_height_m = 0.3;
  double tilt_deg = 10.0;
  StereoDepthOptions depth;
  double pair_tolerance_s = 0.02;  // two cameras (or a third): frames further apart in time are not a set
  double stale_s = 0.15;           // no pair for this long: the link is stale
  double silence_s = 1.0;          // no frame for this long: the nodes are opened anew
  double reconnect_s = 1.0;
};

// Where the camera is, for logs and the devices' list: its node(s), or the name it is looked for by.
inline std::string Where(const StereoCameraOptions& o) {
  std::string where = o.layout == StereoLayout::kTwoCameras ? o.left_node + " + " + o.right_node
                      : o.node.empty()                      ? o.name
                                                            : o.node;
  return o.third_node.empty() ? where : where + " + " + o.third_node;
}

}  // namespace corridor::drivers::stereo
