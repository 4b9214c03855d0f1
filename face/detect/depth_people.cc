#include "face/detect/depth_people.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace corridor::face {
namespace {

// Points this near the floor are the floor around the object's feet, not the object: counted, they put its nearest
// surface on the floor in front of it (0.3 m nearer than the person, in the simulator). A depth camera's floor is
// within a few centimetres of 0 out to several metres.
constexpr double kFloorM = 0.06;

}  // namespace

std::vector<Detection> DepthPeople(const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                                   const std::vector<DepthCandidate>& candidates, const DepthPeopleOptions& options) {
  std::vector<Detection> out;
  if (depth_mm.empty() || depth_mm.type() != CV_16UC1 || depth_mm.cols != camera.width ||
      depth_mm.rows != camera.height || candidates.empty()) {
    return out;
  }
  struct Extent {
    double low = std::numeric_limits<double>::infinity();
    double high = -std::numeric_limits<double>::infinity();
    double near = std::numeric_limits<double>::infinity();
    double left = std::numeric_limits<double>::infinity();  // lateral extent, across the line of sight
    double right = -std::numeric_limits<double>::infinity();
    int u0 = std::numeric_limits<int>::max(), v0 = std::numeric_limits<int>::max(), u1 = -1, v1 = -1;
    int pixels = 0;
    bool top = false;  // it reaches the view's top row
  };
  std::vector<Extent> extents(candidates.size());
  // Every other pixel of every other row: a person at 6 m is still tens of pixels.
  for (int v = 0; v < depth_mm.rows; v += 2) {
    const std::uint16_t* row = depth_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth_mm.cols; u += 2) {
      if (row[u] == 0) continue;
      const Eigen::Vector3d p = camera.base_T_camera * (camera.Ray(u, v) * (row[u] * 0.001));
      if (p.z() < kFloorM) continue;
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        const DepthCandidate& c = candidates[i];
        const Eigen::Vector2d d = p.head<2>() - c.position;
        if (d.norm() > c.radius_m + options.around_m) continue;
        Extent& e = extents[i];
        e.low = std::min(e.low, p.z());
        e.high = std::max(e.high, p.z());
        e.near = std::min(e.near, p.head<2>().norm());
        const Eigen::Vector2d across = Eigen::Vector2d(-c.position.y(), c.position.x()).normalized();
        const double lateral = p.head<2>().dot(across);
        e.left = std::min(e.left, lateral);
        e.right = std::max(e.right, lateral);
        e.u0 = std::min(e.u0, u);
        e.v0 = std::min(e.v0, v);
        e.u1 = std::max(e.u1, u);
        e.v1 = std::max(e.v1, v);
        e.top = e.top || v < 2;
        ++e.pixels;
        break;
      }
    }
  }
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Extent& e = extents[i];
    if (e.pixels < options.min_pixels) continue;
    const double width = e.right - e.left;
    const bool tall = e.high >= options.min_height_m || e.top;
    const bool not_too_tall = e.high <= options.max_height_m || e.top;
    if (!tall || !not_too_tall || e.low > options.max_floor_gap_m || width < options.min_width_m ||
        width > options.max_width_m) {
      continue;
    }
    Detection d;
    d.label = "person";
    d.score = options.score;
    d.source = "depth";
    d.box = cv::Rect2d(e.u0, e.v0, e.u1 - e.u0 + 2, e.v1 - e.v0 + 2);
    const Eigen::Vector2d along = candidates[i].position.normalized();
    d.position = Eigen::Vector3d(along.x() * e.near, along.y() * e.near, std::clamp(e.high / 2.0, 0.5, 1.0));
    d.bearing_rad = std::atan2(candidates[i].position.y(), candidates[i].position.x());
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<Detection> NotAlreadyFound(std::vector<Detection> depth_people, const std::vector<Detection>& people,
                                       double same_m) {
  std::erase_if(depth_people, [&](const Detection& d) {
    return std::any_of(people.begin(), people.end(), [&](const Detection& p) {
      return p.label == "person" && p.position && d.position &&
             (p.position->head<2>() - d.position->head<2>()).norm() <= same_m;
    });
  });
  return depth_people;
}

}  // namespace corridor::face
