#include "nav/ground/morp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace corridor::nav {
namespace {

// The lane's floor line is sampled this finely when it is projected into the image.
constexpr double kLaneStepM = 0.005;
// Below this forward spacing two samples are treated as one vertical surface (no division by ~0).
constexpr float kMinRunM = 0.005f;
// The start pixel s_j moves up to a floor-like pixel only after this much forward run: on a wall (no run) it stays at
// the wall's foot, however little each image row rises there (under 2 mm near the robot); on floors and ramps it
// follows.
constexpr float kMinBaselineM = 0.05f;
// Past the floor line's far end the lane goes on up the image for this much height at the maximum range, so that
// an obstacle standing near max_range_m still shows more than a step's worth of rise.
constexpr double kExtraHeightM = 0.2;

// Projects a base-frame point with the camera's inverse mount taken once (PinholeCamera::Project inverts it per call,
// which dominated building the lanes: 20,000 projections); false behind the camera.
bool ProjectWith(const PinholeCamera& camera, const Eigen::Isometry3d& camera_T_base, const Eigen::Vector3d& point_base,
                 Eigen::Vector2d& pixel) {
  const Eigen::Vector3d p = camera_T_base * point_base;
  if (p.z() <= 1e-9) return false;
  pixel = {camera.fx * p.x() / p.z() + camera.cx, camera.fy * p.y() / p.z() + camera.cy};
  return true;
}

}  // namespace

std::vector<double> LaneOffsets(const MorpOptions& options) {
  const int n = options.lanes > 0 ? options.lanes
                                  : std::max(1, static_cast<int>(std::lround(options.span_m / options.lane_width_m)));
  std::vector<double> offsets;
  for (int j = 0; j < n; ++j) offsets.push_back(options.span_m / 2.0 - (j + 0.5) * options.span_m / n);
  return offsets;
}

double LaneBlindRange(const PinholeCamera& camera, const MorpOptions& options, double offset_m) {
  const Eigen::Isometry3d camera_T_base = camera.base_T_camera.inverse();
  double first_in_view_m = -1.0;  // where the lane's floor enters the image
  for (double x = kLaneStepM; x <= options.max_range_m; x += kLaneStepM) {
    Eigen::Vector2d pixel;
    const Eigen::Vector3d floor(x, offset_m, 0.0);
    if (!ProjectWith(camera, camera_T_base, floor, pixel)) continue;
    const long u = std::lround(pixel.x());
    const double v = std::floor(pixel.y());
    if (u < 0 || u >= camera.width || v < 0.0 || v >= camera.height) continue;
    if (first_in_view_m < 0.0) first_in_view_m = x;
    // ... and where it can first have a depth.
    if (camera.stereo.Sees(pixel.x(), (camera_T_base * floor).z())) {
      return options.blind_range_m + (x - first_in_view_m);
    }
  }
  return options.blind_range_m;
}

Morp::Morp(const PinholeCamera& camera, const MorpOptions& options) : camera_(camera), options_(options) {
  if (!camera.Valid()) throw std::invalid_argument("Morp: the camera needs a positive size and focal length");
  if (!(options.span_m > 0.0) || !(options.lane_width_m > 0.0) || !(options.max_range_m > options.min_range_m)) {
    throw std::invalid_argument("Morp: widths must be positive and max_range_m above min_range_m");
  }
  const Eigen::Vector3f origin = camera.base_T_camera.translation().cast<float>();
  const Eigen::Matrix3d rotation = camera.base_T_camera.linear();
  const Eigen::Isometry3d camera_T_base = camera.base_T_camera.inverse();
  for (const double offset : LaneOffsets(options)) {
    Lane lane;
    lane.offset_m = offset;
    int last_row = camera.height;
    bool seen = false;
    for (double x = kLaneStepM; x <= options.max_range_m; x += kLaneStepM) {
      Eigen::Vector2d pixel;
      const Eigen::Vector3d floor(x, lane.offset_m, 0.0);
      if (!ProjectWith(camera, camera_T_base, floor, pixel)) continue;
      const int u = static_cast<int>(std::lround(pixel.x()));
      const int v = static_cast<int>(std::floor(pixel.y()));
      if (u < 0 || u >= camera.width || v < 0 || v >= camera.height) continue;
      // In a stereo pair's shadow the floor has no true depth, and nothing nearer has one either: a depth found
      // there is a mismatch (farther than the floor, so it would read as a drop). The lane starts past it.
      if (!seen) {
        if (!camera.stereo.Sees(pixel.x(), (camera_T_base * floor).z())) continue;
        seen = true;
      }
      if (v >= last_row) continue;  // one sample per row, rising as the floor line recedes
      last_row = v;
      lane.samples.push_back({u, v, origin, (rotation * camera.Ray(u + 0.5, v + 0.5)).cast<float>()});
    }
    lane.blind_range_m = LaneBlindRange(camera, options, lane.offset_m);
    if (lane.samples.size() >= 2) {
      // Continue up the image along the lane line's direction.
      const Sample& a = lane.samples[lane.samples.size() - 2];
      const Sample& b = lane.samples.back();
      const double du_per_row = static_cast<double>(b.u - a.u) / std::max(1, a.v - b.v);
      const int extra = static_cast<int>(std::ceil(camera.fy * kExtraHeightM / options.max_range_m));
      for (int i = 1; i <= extra && b.v - i >= 0; ++i) {
        const int u = static_cast<int>(std::lround(b.u + du_per_row * i));
        if (u < 0 || u >= camera.width) break;
        lane.samples.push_back({u, b.v - i, origin, (rotation * camera.Ray(u + 0.5, b.v - i + 0.5)).cast<float>()});
      }
    }
    lanes_.push_back(std::move(lane));
  }
  results_.resize(lanes_.size());
}

const std::vector<LaneResult>& Morp::Process(const cv::Mat& depth) {
  const bool millimetres = depth.type() == CV_16UC1;
  if ((!millimetres && depth.type() != CV_32FC1) || depth.cols != camera_.width || depth.rows != camera_.height) {
    throw std::invalid_argument("Morp: expected a " + std::to_string(camera_.width) + "x" +
                                std::to_string(camera_.height) + " depth image, CV_16UC1 (mm) or CV_32FC1 (m)");
  }
  const int k = options_.half_window_px;
  const float max_step = static_cast<float>(options_.max_step_m);
  const float max_drop = static_cast<float>(options_.max_drop_m);
  const float threshold = static_cast<float>(options_.score_threshold);
  const float w1 = static_cast<float>(options_.w1);
  const float w2 = static_cast<float>(options_.w2);
  // The nearest valid depth (metres) across the lane's window on one row, or 0 for none.
  const auto depth_at = [&](int u, int v) {
    float best = 0.0f;
    const int u0 = std::max(0, u - k);
    const int u1 = std::min(camera_.width - 1, u + k);
    for (int c = u0; c <= u1; ++c) {
      const float d = millimetres ? depth.ptr<std::uint16_t>(v)[c] * 0.001f : depth.ptr<float>(v)[c];
      if (d > 0.0f && std::isfinite(d) && (best == 0.0f || d < best)) best = d;
    }
    return best;
  };

  for (std::size_t j = 0; j < lanes_.size(); ++j) {
    const Lane& lane = lanes_[j];
    LaneResult& out = results_[j];
    out = LaneResult{};
    out.offset_m = lane.offset_m;
    bool started = false;
    float r_first = 0.0f;  // the first valid pixel's forward distance: how near the robot the lane is seen
    float r_start = 0.0f;
    float z_start = 0.0f;
    float r_prev = 0.0f;
    float z_prev = 0.0f;
    float last_floor_r = 0.0f;
    for (const Sample& s : lane.samples) {
      const float d = depth_at(s.u, s.v);
      if (d <= 0.0f) continue;  // a hole: no evidence either way
      const Eigen::Vector3f p = s.origin + s.ray * d;
      const float r = p.x();
      const float z = p.z();
      bool dead = false;
      if (!started) {
        started = true;
        r_first = r_start = r_prev = r;
        z_start = z_prev = z;
        dead = std::abs(z) > max_step;  // something already stands (or gapes) at the bottom of the view
      } else {
        // DPoom eq. (2)-(3): the local slope and the slope from the lane's start pixel, weighted.
        const float local = std::abs(z - z_prev) / std::max(std::abs(r - r_prev), kMinRunM);
        const float global = std::abs(z - z_start) / std::max(std::abs(r - r_start), kMinRunM);
        const bool steep = w1 * local + w2 * global > threshold;
        dead = (steep && std::abs(z - z_start) > max_step) || z < -max_drop;
        if (!dead && !steep && r - r_start >= kMinBaselineM) {  // floor-like: the next rise is measured from here
          r_start = r;
          z_start = z;
        }
        r_prev = r;
        z_prev = z;
      }
      if (dead) {
        out.dead_end = true;
        // A rise: free up to the dead-end pixel itself (steep means it stands where it starts; the last floor pixel
        // can be a whole image row, ~10 cm at 3.5 m, short of it). A drop: free up to the last floor pixel, the
        // edge, since the lower floor is first seen much farther out, past the edge's shadow.
        const float last_free = last_floor_r > 0.0f ? last_floor_r : r;
        const float free = z >= z_start ? r : std::min(r, last_free);
        out.free_distance_m = std::max(0.0, static_cast<double>(free));
        out.pixel = {s.u, s.v};
        out.point = p.cast<double>();
        break;
      }
      if (r > options_.max_range_m) break;
      last_floor_r = r;
    }
    if (!out.dead_end) {
      if (!started || r_first > lane.blind_range_m) {
        // Nothing seen near the robot: too close to something to measure, or a blinded camera. Stop.
        out.blind = true;
        out.dead_end = true;
        out.free_distance_m = options_.min_range_m;
      } else {
        // Free as far as the floor was seen; beyond the last valid floor pixel nothing is known.
        out.free_distance_m = std::min(options_.max_range_m, static_cast<double>(last_floor_r));
      }
    }
  }
  return results_;
}

int LaneOnLine(const MorpOptions& options, int lanes, double y_m) {
  const double spacing = options.span_m / lanes;
  // Lanes run left (+y) to right, `spacing` apart from the first at span_m / 2 - spacing / 2.
  const double from_first = (options.span_m / 2.0 - spacing / 2.0 - y_m) / spacing;
  const long j = std::lround(from_first);
  if (j < 0 || j >= lanes || std::abs(from_first - static_cast<double>(j)) > 0.25) return -1;
  return static_cast<int>(j);
}

double NearestDeadEnd(const std::vector<LaneResult>& lanes, double half_width_m) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const LaneResult& lane : lanes) {
    if (lane.dead_end && std::abs(lane.offset_m) <= half_width_m) nearest = std::min(nearest, lane.free_distance_m);
  }
  return nearest;
}

}  // namespace corridor::nav
