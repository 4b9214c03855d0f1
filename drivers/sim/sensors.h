// Simulated sensors: a ray-cast RGB-D camera with a structured-light noise model, and a planar laser.
#pragma once

#include <random>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "drivers/sim/ray_caster.h"

namespace corridor::drivers::sim {

struct SimCameraOptions {
  int width = 320;
  int height = 240;
  double horizontal_fov_deg = 85.2;  // Intel RealSense D435 depth, as on DPoom
  double vertical_fov_deg = 58.0;
  double mount_x_m = 0.1;       // forward of the base centre
  double mount_height_m = 0.3;  // optical centre above the floor
  double tilt_deg = 10.0;       // pitched down
  double min_range_m = 0.2;
  double max_range_m = 6.0;
  double rate_hz = 15.0;
  // Axial noise sigma(z) = a + b * z^2, the usual structured-light model (Nguyen et al., 3DIMPVT 2012).
  double noise_a_m = 0.0012;
  double noise_b_per_m = 0.0019;
  double dropout_fraction = 0.02;    // pixels lost at random
  double grazing_cutoff_deg = 87.0;  // surfaces seen more obliquely than this return nothing (floor beyond
                                     // about 5.7 m for a camera 0.3 m up)
};

// The camera on a pan servo (sim.camera.pan): turned toward its target at max_speed_dps about a vertical axis,
// reporting its angle rate_hz times a second as a servo's driver does.
struct SimPanOptions {
  bool enabled = false;
  double axis_x_m = 0.1;  // the axis in the base frame (under the camera's optical centre: its mount_x_m)
  double axis_y_m = 0.0;
  double min_deg = -150.0;
  double max_deg = 150.0;
  double max_speed_dps = 90.0;
  double rate_hz = 50.0;
};

struct SimLaserOptions {
  bool enabled = true;
  int beams = 360;
  double mount_height_m = 0.2;
  double min_range_m = 0.12;
  double max_range_m = 8.0;
  double rate_hz = 10.0;
  double noise_m = 0.01;
  // Where the configuration says the laser points (base_T_laser); the simulated laser really faces forward. Not 0:
  // a laser whose mounting is set wrong, as the laser's calibration finds.
  double mount_yaw_deg = 0.0;
  // A rotating laser (an RPLIDAR's, an LDS's): each beam measured as the laser turns clockwise past it from forward,
  // once every 1 / rate_hz, from where the robot is then (to the physics step); its scans carry that timing. False:
  // every beam at once.
  bool sweep = false;
};

// Intrinsics and mounting of the simulated camera.
CameraInfo MakeCameraInfo(const SimCameraOptions& options);

// Renders one RGB-D frame from the camera at world_T_camera (optical frame). Draws noise from `rng`.
// Colour is each triangle's colour, lit from the camera; depth follows the options' range, noise and holes.
class RgbdRenderer {
 public:
  RgbdRenderer(const RayCaster& caster, const SimCameraOptions& options);
  void Render(const Eigen::Isometry3d& world_T_camera, std::mt19937& rng, RgbdFrame& frame) const;
  // The colour image alone (CV_8UC3), as a plain camera sees it: one view of a stereo pair. The surfaces' colours
  // vary over a few centimetres by `texture` (SurfaceTexture; 0: flat colours, as Render draws them), and each pixel
  // gets Gaussian sensor noise of `noise_levels` grey levels.
  void RenderColor(const Eigen::Isometry3d& world_T_camera, double texture, double noise_levels, std::mt19937& rng,
                   cv::Mat& bgr) const;

 private:
  // Every pixel's ray from the camera at world_T_camera (world frame, z = 1 in the optical frame) and what it hits.
  void CastPixels(const Eigen::Isometry3d& world_T_camera, std::vector<Eigen::Vector3f>& directions,
                  std::vector<RayHit>& hits) const;

  const RayCaster& caster_;
  SimCameraOptions options_;
  CameraInfo info_;
  std::vector<Eigen::Vector3f> rays_;  // per pixel, optical frame, z = 1 so that t is the depth
};

// The surfaces' texture at a world point, in [0, 1]: value noise at 4 and 1.5 cm, the same from every viewpoint (as a
// surface's own pattern is), smooth enough for a camera's pixels to sample.
float SurfaceTexture(const Eigen::Vector3f& point_m);

// Casts one laser sweep from the laser at world_T_laser (x forward, z up), ranges with Gaussian noise.
void CastScan(const RayCaster& caster, const Eigen::Isometry3d& world_T_laser, const SimLaserOptions& options,
              std::mt19937& rng, LaserScan& scan);
// A scan of the options' beams with nothing measured yet (every range +infinity).
void StartScan(const SimLaserOptions& options, LaserScan& scan);
// Casts the beams `first` to `last` (exclusive) of a rotating laser's order (clockwise from forward: beam k at k
// beams' angle clockwise) into `scan` (StartScan's), from the laser at world_T_laser.
void CastBeams(const RayCaster& caster, const Eigen::Isometry3d& world_T_laser, const SimLaserOptions& options,
               std::mt19937& rng, int first, int last, LaserScan& scan);

}  // namespace corridor::drivers::sim
