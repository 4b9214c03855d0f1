#include "face/detect/locate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::face {

SizeLimits PersonSize() { return {0.2, 1.6, 0.8, 2.6}; }
SizeLimits FaceSize() { return {0.08, 0.45, 0.08, 0.45}; }

std::optional<Located> Locate(const cv::Rect2d& box, const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                              const LocateOptions& options) {
  if (depth_mm.type() != CV_16UC1 || depth_mm.cols != camera.width || depth_mm.rows != camera.height) {
    throw std::invalid_argument("locate: depth must be CV_16UC1 of the camera's size");
  }
  // The box's middle, clipped to the image.
  const cv::Rect image(0, 0, depth_mm.cols, depth_mm.rows);
  const cv::Rect middle = cv::Rect(static_cast<int>(std::floor(box.x + box.width * 0.25)),
                                   static_cast<int>(std::floor(box.y + box.height * 0.2)),
                                   std::max(1, static_cast<int>(std::lround(box.width * 0.5))),
                                   std::max(1, static_cast<int>(std::lround(box.height * 0.6)))) &
                          image;
  if (middle.empty()) return std::nullopt;
  const int step = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(middle.area()) / options.max_samples)));
  std::vector<double> depths;
  for (int v = middle.y; v < middle.y + middle.height; v += step) {
    const auto* row = depth_mm.ptr<std::uint16_t>(v);
    for (int u = middle.x; u < middle.x + middle.width; u += step) {
      const double d = row[u] * 0.001;
      if (d >= options.min_depth_m && d <= options.max_depth_m) depths.push_back(d);
    }
  }
  if (depths.empty()) return std::nullopt;
  const auto at = depths.begin() + static_cast<long>(options.depth_fraction * static_cast<double>(depths.size() - 1));
  std::nth_element(depths.begin(), at, depths.end());
  Located out;
  out.depth_m = *at;
  const Eigen::Vector3d optical = camera.Ray(box.x + box.width / 2.0, box.y + box.height / 2.0) * out.depth_m;
  out.position = camera.base_T_camera * optical;
  out.width_m = box.width * out.depth_m / camera.fx;
  out.height_m = box.height * out.depth_m / camera.fy;
  return out;
}

bool Plausible(const Located& located, const cv::Rect2d& box, cv::Size image, const SizeLimits& limits) {
  constexpr double kEdgePx = 2.0;
  const bool cut_across = box.x <= kEdgePx || box.x + box.width >= image.width - kEdgePx;
  const bool cut_down = box.y <= kEdgePx || box.y + box.height >= image.height - kEdgePx;
  if (!cut_across && (located.width_m < limits.min_width_m || located.width_m > limits.max_width_m)) return false;
  if (!cut_down && (located.height_m < limits.min_height_m || located.height_m > limits.max_height_m)) return false;
  return true;
}

void LocateDetections(std::vector<Detection>& detections, const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                      const LocateOptions& options) {
  std::erase_if(detections, [&](Detection& d) {
    bool implausible = false;
    if (d.box && !depth_mm.empty()) {
      if (const std::optional<Located> located = Locate(*d.box, depth_mm, camera, options)) {
        d.position = located->position;
        if (d.label == "person") implausible = !Plausible(*located, *d.box, depth_mm.size(), PersonSize());
        if (d.label == "face") implausible = !Plausible(*located, *d.box, depth_mm.size(), FaceSize());
      }
    }
    // Its direction: from where it is when that is known, else along the ray through its box's middle.
    if (d.position) {
      d.bearing_rad = std::atan2(d.position->y(), d.position->x());
    } else if (d.box) {
      const Eigen::Vector3d ray =
          camera.base_T_camera.linear() * camera.Ray(d.box->x + d.box->width / 2.0, d.box->y + d.box->height / 2.0);
      d.bearing_rad = std::atan2(ray.y(), ray.x());
    }
    return implausible;
  });
}

}  // namespace corridor::face
