// A pinhole depth camera mounted on the robot: intrinsics in pixels and its pose in the base frame (x forward, y left,
// z up, origin on the floor under the robot's centre). The optical frame is x right, y down, z forward.
#pragma once

#include <vector>

#include <Eigen/Geometry>

namespace corridor::nav {

// Where a stereo pair measures depth, its left image being the camera's: a point at depth z seen in column u is in
// the right image at u - focal * baseline / z, and has a depth only when that lies at least edge_px inside the right
// image (nearer its edge the matcher's window reaches past it). So the pair is blind close by on its left side: with
// 12 cm between 174 px cameras, a lane 0.45 m to the left is first seen 0.7 m ahead. A depth sensor has no such
// shadow (focal_baseline_px_m 0).
struct StereoShadow {
  double focal_baseline_px_m = 0.0;  // the rectified focal length times the baseline
  double edge_px = 0.0;

  // Whether a point at `depth_m` in column `u` can have a depth.
  bool Sees(double u, double depth_m) const {
    return focal_baseline_px_m <= 0.0 || (depth_m > 0.0 && u - focal_baseline_px_m / depth_m >= edge_px);
  }
};

struct PinholeCamera {
  int width = 0;
  int height = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();
  StereoShadow stereo;  // a stereo pair's (else none)

  // A size and focal lengths a projection can use (positive).
  bool Valid() const { return width > 0 && height > 0 && fx > 0.0 && fy > 0.0; }
  // The ray through pixel (u, v) in the optical frame, scaled so that its z is 1: depth times it is the point.
  Eigen::Vector3d Ray(double u, double v) const { return {(u - cx) / fx, (v - cy) / fy, 1.0}; }
  // Projects a base-frame point; false when it is behind the camera.
  bool Project(const Eigen::Vector3d& point_base, Eigen::Vector2d& pixel) const {
    const Eigen::Vector3d p = base_T_camera.inverse() * point_base;
    if (p.z() <= 1e-9) return false;
    pixel = {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
    return true;
  }
};

// The pose in the base frame of a camera looking straight ahead, `x_m` forward of the base's centre, its optical
// centre `height_m` above the floor, pitched down by `tilt_rad`.
inline Eigen::Isometry3d CameraMount(double x_m, double height_m, double tilt_rad) {
  Eigen::Matrix3d base_R_optical;  // optical z forward, x right, y down
  base_R_optical.col(0) = Eigen::Vector3d(0, -1, 0);
  base_R_optical.col(1) = Eigen::Vector3d(0, 0, -1);
  base_R_optical.col(2) = Eigen::Vector3d(1, 0, 0);
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();
  base_T_camera.linear() = Eigen::AngleAxisd(tilt_rad, Eigen::Vector3d::UnitY()) * base_R_optical;
  base_T_camera.translation() = Eigen::Vector3d(x_m, 0.0, height_m);
  return base_T_camera;
}

// A pan servo's turn: pan_rad counter-clockwise (seen from above) about a vertical axis through `axis_xy` of the base
// frame. It carries a camera's pose at rest to its pose turned (PanTurn(axis, pan) * base_T_camera), and a base's pose
// in the world to the "turned base" the camera at rest is mounted on (world_T_base * PanTurn(axis, pan)).
inline Eigen::Isometry3d PanTurn(const Eigen::Vector2d& axis_xy, double pan_rad) {
  const Eigen::Vector3d axis(axis_xy.x(), axis_xy.y(), 0.0);
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(pan_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turn.translation() = axis - turn.linear() * axis;
  return turn;
}

// The same camera at another pose (a panned one).
inline PinholeCamera AtPose(PinholeCamera camera, const Eigen::Isometry3d& base_T_camera) {
  camera.base_T_camera = base_T_camera;
  return camera;
}

// Whether two poses of a camera differ by more than a reader's precomputed rays tolerate (0.1 mm, 0.1 mrad).
inline bool Moved(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm() > 1e-4 || !a.linear().isApprox(b.linear(), 1e-4);
}

// The rays through the pixels of every row_step-th row (row-major), turned into the base frame and scaled like Ray:
// the camera's position plus depth times a ray is the pixel's point in the base frame. Precomputed once by those
// that read every frame's pixels.
inline std::vector<Eigen::Vector3f> BaseFrameRays(const PinholeCamera& camera, int row_step = 1) {
  const Eigen::Matrix3d rotation = camera.base_T_camera.linear();
  std::vector<Eigen::Vector3f> rays;
  rays.reserve(static_cast<std::size_t>(camera.width) * ((camera.height + row_step - 1) / row_step));
  for (int v = 0; v < camera.height; v += row_step) {
    for (int u = 0; u < camera.width; ++u) rays.push_back((rotation * camera.Ray(u, v)).cast<float>());
  }
  return rays;
}

}  // namespace corridor::nav
