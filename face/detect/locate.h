// Where a detection is, from the depth inside its box, and whether an object of that size at that distance can be
// what the detector says it is (a person's box 3 m tall, or one on a poster 6 m away seen as 30 cm, is not a person).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "face/detect/detection.h"
#include "nav/geometry/camera_model.h"

namespace corridor::face {

struct LocateOptions {
  double min_depth_m = 0.2;
  double max_depth_m = 10.0;
  // The depths sampled in the box's middle (its middle half across, from a fifth to four fifths down) are sorted and
  // this fraction taken: the object's near surface rather than the wall seen past its edges.
  double depth_fraction = 0.25;
  int max_samples = 500;
};

// The size in metres an object of a kind may have; a bound is skipped when the box touches the image's edge on that
// axis (the object is cut).
struct SizeLimits {
  double min_width_m = 0.0;
  double max_width_m = 1e9;
  double min_height_m = 0.0;
  double max_height_m = 1e9;
};
SizeLimits PersonSize();  // a whole body, standing or sitting, children too: 0.2-1.6 m wide, 0.8-2.6 m tall
SizeLimits FaceSize();    // 0.08-0.45 m either way

struct Located {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // base frame: the ray through the box's middle at depth_m
  double depth_m = 0.0;
  double width_m = 0.0;  // the box's size at depth_m
  double height_m = 0.0;
};

// The object in `box` (colour pixels; the depth is registered to them) seen by `camera`: nullopt when its middle has
// no depth within the limits. Throws std::invalid_argument for depth that is not CV_16UC1 of the camera's size.
std::optional<Located> Locate(const cv::Rect2d& box, const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                              const LocateOptions& options = {});

// Whether `located` is within `limits` (bounds on an axis the box is cut on by the image's edge are skipped).
bool Plausible(const Located& located, const cv::Rect2d& box, cv::Size image, const SizeLimits& limits);

// Sets each detection's position from the depth and drops the ones whose size rules them out (people and faces by
// PersonSize and FaceSize; other labels are only located). Detections without a box or depth are kept unlocated.
// Every detection with a box or a position gets its bearing (from the box's middle when there is no depth).
void LocateDetections(std::vector<Detection>& detections, const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                      const LocateOptions& options = {});

}  // namespace corridor::face
