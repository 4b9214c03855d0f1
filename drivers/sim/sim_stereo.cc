#include "drivers/sim/sim_stereo.h"

#include <cmath>
#include <numbers>

namespace corridor::drivers::sim {

SimCameraOptions StereoViewOptions(const SimCameraOptions& camera) {
  SimCameraOptions views = camera;
  const double fx = MakeCameraInfo(camera).camera.fx;
  views.vertical_fov_deg = 2.0 * std::atan(camera.height / (2.0 * fx)) * 180.0 / std::numbers::pi;
  return views;
}

stereo::StereoCalibration IdealStereoCalibration(const SimCameraOptions& camera, double baseline_m) {
  const nav::PinholeCamera k = MakeCameraInfo(StereoViewOptions(camera)).camera;
  stereo::StereoCalibration c;
  c.image_size = {k.width, k.height};
  // The renderer's pixel centres are at u + 0.5 from the image's edge: OpenCV's principal point is in pixel indices.
  c.left.matrix = cv::Matx33d(k.fx, 0.0, k.cx - 0.5, 0.0, k.fy, k.cy - 0.5, 0.0, 0.0, 1.0);
  c.right = c.left;
  c.translation_m = {-baseline_m, 0.0, 0.0};
  return c;
}

namespace {

stereo::StereoDepthOptions DepthOptions(const SimCameraOptions& camera, const SimStereoOptions& options) {
  stereo::StereoDepthOptions depth = options.depth;
  depth.width = std::min(depth.width, camera.width);
  return depth;
}

}  // namespace

SimStereoCamera::SimStereoCamera(const RayCaster& caster, const SimCameraOptions& camera,
                                 const SimStereoOptions& options)
    : renderer_(caster, StereoViewOptions(camera)),
      options_(options),
      base_T_left_(MakeCameraInfo(camera).camera.base_T_camera),
      depth_(IdealStereoCalibration(camera, options.baseline_m),
             options.wide_baseline_m > 0.0
                 ? std::optional<stereo::StereoCalibration>(IdealStereoCalibration(camera, options.wide_baseline_m))
                 : std::nullopt,
             base_T_left_, DepthOptions(camera, options), options.wide_disparities, options.fusion) {}

void SimStereoCamera::Render(const Eigen::Isometry3d& world_T_base, std::mt19937& rng, RgbdFrame& frame) {
  RenderViews(world_T_base, rng);
  Match(frame);
}

void SimStereoCamera::RenderViews(const Eigen::Isometry3d& world_T_base, std::mt19937& rng) {
  const Eigen::Isometry3d world_T_left = world_T_base * base_T_left_;
  renderer_.RenderColor(world_T_left, options_.texture, options_.image_noise, rng, left_);
  // The right camera: the baseline along the left one's x axis (its right).
  const Eigen::Isometry3d world_T_right = world_T_left * Eigen::Translation3d(options_.baseline_m, 0.0, 0.0);
  renderer_.RenderColor(world_T_right, options_.texture, options_.image_noise, rng, right_);
  if (options_.wide_baseline_m > 0.0) {
    const Eigen::Isometry3d world_T_third = world_T_left * Eigen::Translation3d(options_.wide_baseline_m, 0.0, 0.0);
    renderer_.RenderColor(world_T_third, options_.texture, options_.image_noise, rng, third_);
  }
}

}  // namespace corridor::drivers::sim
