#include "face/detect/simulated_people.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::face {

SimulatedPeople::SimulatedPeople(const SimulatedPeopleOptions& options) : options_(options), random_(options.seed) {
  if (!(options.miss_rate >= 0.0 && options.miss_rate <= 1.0) || !(options.radius_m > 0.0) ||
      !(options.height_m > 0.0) || !(options.max_range_m > 0.0)) {
    throw std::invalid_argument("simulated people: miss_rate within [0, 1], sizes and range positive");
  }
}

std::vector<Detection> SimulatedPeople::Detect(const std::vector<Eigen::Vector2d>& people,
                                               const nav::Pose2& world_T_base, const cv::Mat& depth_mm,
                                               const nav::PinholeCamera& camera) {
  std::vector<Detection> out;
  const nav::Pose2 base_T_world = world_T_base.Inverse();
  const Eigen::Isometry3d camera_T_base = camera.base_T_camera.inverse();
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const Eigen::Vector2d& person : people) {
    const Eigen::Vector2d p = base_T_world.Transform(person);
    const double range = p.norm();
    if (range > options_.max_range_m || range <= options_.radius_m) continue;
    // The near surface, and the body's corners, in the optical frame.
    const Eigen::Vector2d near = p * ((range - options_.radius_m) / range);
    const Eigen::Vector2d side = Eigen::Vector2d(-p.y(), p.x()).normalized() * options_.radius_m;
    double u_min = 1e9, u_max = -1e9, v_min = 1e9, v_max = -1e9;
    bool behind = false;
    for (const double z : {0.0, options_.height_m}) {
      for (const Eigen::Vector2d& xy : {Eigen::Vector2d(near + side), Eigen::Vector2d(near - side)}) {
        const Eigen::Vector3d c = camera_T_base * Eigen::Vector3d(xy.x(), xy.y(), z);
        if (c.z() <= 0.05) {
          behind = true;
          continue;
        }
        const double u = camera.fx * c.x() / c.z() + camera.cx;
        const double v = camera.fy * c.y() / c.z() + camera.cy;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        v_min = std::min(v_min, v);
        v_max = std::max(v_max, v);
      }
    }
    if (behind) continue;
    // In view: at least a fifth of the body (a person close in front shows the camera their legs only), and half its
    // width.
    const cv::Rect2d box(u_min, v_min, u_max - u_min, v_max - v_min);
    const cv::Rect2d clipped = box & cv::Rect2d(0, 0, camera.width, camera.height);
    if (clipped.area() < 0.2 * box.area() || clipped.width < 0.5 * box.width) continue;
    const cv::Point2d middle(clipped.x + clipped.width / 2.0, clipped.y + clipped.height / 2.0);
    const Eigen::Vector3d position(near.x(), near.y(), options_.height_m / 2.0);
    if (!depth_mm.empty()) {
      const int u = std::clamp(static_cast<int>(middle.x), 0, depth_mm.cols - 1);
      const int v = std::clamp(static_cast<int>(middle.y), 0, depth_mm.rows - 1);
      const double depth = depth_mm.at<std::uint16_t>(v, u) * 0.001;
      const double own = (camera_T_base * position).z();
      if (depth > 0.0 && depth < own - options_.hidden_margin_m) continue;  // a wall in between
    }
    if (uniform(random_) < options_.miss_rate) continue;
    out.push_back({"person", 0.9, clipped, position, 0, "sim"});
  }
  return out;
}

}  // namespace corridor::face
