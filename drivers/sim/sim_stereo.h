// The simulator's stereo camera: two views rendered a baseline apart (textured surfaces, sensor noise) and handed to
// the same depth path as a real stereo camera's (drivers/stereo/stereo_depth.h), so that the robot navigates on
// depth from matching, with its holes and errors, instead of a depth sensor's.
#pragma once

#include <memory>
#include <random>

#include "drivers/sim/sensors.h"
#include "drivers/stereo/multi_baseline.h"
#include "drivers/stereo/stereo_depth.h"

namespace corridor::drivers::sim {

struct SimStereoOptions {
  bool enabled = false;      // the simulated camera is a stereo pair (else a depth sensor: SimCameraOptions' model)
  double baseline_m = 0.12;  // ASNS's narrow pair
  // A third view this far to the left one's right makes the wide pair (ASNS's: 0.24 m), fused with the narrow one
  // (stereo::MultiBaselineDepth); 0: the narrow pair alone. The wide pair is matched over wide_disparities: 64 at the
  // views' 174 px focal length reach from 0.65 m, nearer than the wide pair's band begins.
  double wide_baseline_m = 0.0;
  int wide_disparities = 64;
  stereo::BaselineFusionOptions fusion;
  double image_noise = 2.0;  // each view's sensor noise, grey levels (sigma)
  // The surfaces' texture (RgbdRenderer::RenderColor): what matching finds; 0 leaves flat colours, on which a stereo
  // camera finds nothing, as a real one would not on a plain wall.
  double texture = 0.5;
  // The depth path as on a robot: matched and given at the views' size unless depth.width is smaller. 80 disparities:
  // the simulated camera's 320 px across 85 degrees (a focal length of 174 px) with 12 cm between the views see from
  // 0.26 m on. A texture threshold of twice the views' noise: blocks of pure noise (the plain background above the
  // walls) vary by about 2 grey levels, and at 2.5 a few were matched each frame into obstacles half a metre away.
  stereo::StereoDepthOptions depth = [] {
    stereo::StereoDepthOptions d;
    d.matcher.disparities = 80;
    d.matcher.min_texture = 4.0;
    return d;
  }();
};

// The views' camera: the configured one with square pixels, as a stereo pair's cameras have (the depth sensor's
// default, 85 by 58 degrees on 320 x 240, has not): the horizontal field kept, the vertical one from it. Rectifying
// non-square pixels would crop the width to the height's focal length, 73 degrees across instead of 85.
SimCameraOptions StereoViewOptions(const SimCameraOptions& camera);

// An ideal pair of the views' camera (StereoViewOptions), no distortion, the right camera `baseline_m` to the left
// one's right: what calibrating the simulated pair (or the left camera with the third) would give.
stereo::StereoCalibration IdealStereoCalibration(const SimCameraOptions& camera, double baseline_m);

class SimStereoCamera {
 public:
  // Renders the views of `camera` (StereoViewOptions) with `caster`, which must outlive this. Throws
  // std::invalid_argument for depth options that cannot work.
  SimStereoCamera(const RayCaster& caster, const SimCameraOptions& camera, const SimStereoOptions& options);

  // The rectified left camera the frames are in (the configured camera's mounting and intrinsics).
  const CameraInfo& info() const { return depth_.info(); }

  // Renders the views from the robot's base at world_T_base and matches them into `frame`: RenderViews, then Match.
  void Render(const Eigen::Isometry3d& world_T_base, std::mt19937& rng, RgbdFrame& frame);
  // The two steps on their own (the depth path's time is Match's).
  void RenderViews(const Eigen::Isometry3d& world_T_base, std::mt19937& rng);
  void Match(RgbdFrame& frame) { depth_.Process(left_, right_, third_, frame); }

 private:
  RgbdRenderer renderer_;
  SimStereoOptions options_;
  Eigen::Isometry3d base_T_left_;  // the configured mounting of the left camera
  stereo::MultiBaselineDepth depth_;
  cv::Mat left_, right_, third_;  // third_: the wide pair's right view, when there is one
};

}  // namespace corridor::drivers::sim
