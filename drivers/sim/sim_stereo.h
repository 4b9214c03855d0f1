// The simulator's stereo camera: two views rendered a baseline apart (textured surfaces, sensor noise) and handed to
// the same depth path as a real stereo camera's (drivers/stereo/stereo_depth.h), so that the robot navigates on
// depth from matching, with its holes and errors, instead of a depth sensor's.
#pragma once

#include <memory>
#include <random>

#include "drivers/sim/sensors.h"
#include "drivers/stereo/stereo_depth.h"

namespace corridor::drivers::sim {

struct SimStereoOptions {
  bool enabled = false;      // the simulated camera is a stereo pair (else a depth sensor: SimCameraOptions' model)
  double baseline_m = 0.12;  // ASNS's narrow pair; its wide one is 0.24
  double image_noise = 2.0;  // each view's sensor noise, grey levels (sigma)
  // The surfaces' texture (RgbdRenderer::RenderColor): what matching finds; 0 leaves flat colours, on which a stereo
  // camera finds nothing, as a real one would not on a plain wall.
  double texture = 0.5;
  // The depth path as on a robot: matched and given at the views' size unless depth.width is smaller. 80 disparities:
  // the simulated camera's 320 px across 85 degrees (a focal length of 174 px) with 12 cm between the views see from
  // 0.26 m on.
  stereo::StereoDepthOptions depth = [] {
    stereo::StereoDepthOptions d;
    d.matcher.disparities = 80;
    return d;
  }();
};

// An ideal pair of the simulated camera's intrinsics, no distortion, the right camera `baseline_m` to the left one's
// right: what calibrating the simulated pair would give.
stereo::StereoCalibration IdealStereoCalibration(const SimCameraOptions& camera, double baseline_m);

class SimStereoCamera {
 public:
  // `renderer` renders one view (the camera's options, its texture) and must outlive this. Throws
  // std::invalid_argument for depth options that cannot work.
  SimStereoCamera(const RgbdRenderer& renderer, const SimCameraOptions& camera, const SimStereoOptions& options);

  // The rectified left camera the frames are in (the configured camera's mounting and intrinsics).
  const CameraInfo& info() const { return depth_.info(); }

  // Renders both views from the robot's base at world_T_base and matches them into `frame`.
  void Render(const Eigen::Isometry3d& world_T_base, std::mt19937& rng, RgbdFrame& frame);

 private:
  const RgbdRenderer& renderer_;
  SimStereoOptions options_;
  Eigen::Isometry3d base_T_left_;  // the configured mounting of the left camera
  stereo::StereoDepth depth_;
  cv::Mat left_, right_;
};

}  // namespace corridor::drivers::sim
