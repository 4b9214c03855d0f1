// People in the depth image: an object the robot's tracker found (nav/tracking, a cluster of the depth camera's or the
// laser's scan) is a person when the depth image shows it person-shaped where it stands: standing on the floor, tall
// (reaching up to min_height_m, or past the top of the view), not as tall as a pillar, about a person's width. What
// the colour image's detector misses (someone a metre away, their head above the view; someone sideways, sitting,
// in the dark) the depth camera still sees; what it finds with no person-shaped depth behind it is kept as it is (the
// depth may be missing). Where a depth image exists (a RealSense, the simulator), PerceptionNode adds these to the
// colour image's people; it is not used on images without depth.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "face/detect/detection.h"
#include "nav/geometry/camera_model.h"

namespace corridor::face {

struct DepthPeopleOptions {
  double min_height_m = 1.2;      // the highest point seen of it, above the floor (a sitting adult, a child)
  double max_height_m = 2.1;      // a pillar or a shelf reaching higher is not a person (unless cut by the view's top)
  double max_floor_gap_m = 0.35;  // its lowest point seen: standing on the floor (a table's top is not)
  double min_width_m = 0.15;
  double max_width_m = 1.0;
  double around_m = 0.15;  // pixels this far beyond the object's radius from its centre are part of it
  int min_pixels = 30;
  double score = 0.5;
};

// An object of the tracker, in the base frame (the robot's, x forward, y left).
struct DepthCandidate {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
};

// The candidates the depth image shows person-shaped, as person detections (source "depth"): their box the pixels
// that make them, their position the object's nearest surface (base frame). `depth_mm` CV_16UC1 of the camera's size
// (0: no measurement); an empty or mismatched image gives none.
std::vector<Detection> DepthPeople(const cv::Mat& depth_mm, const nav::PinholeCamera& camera,
                                   const std::vector<DepthCandidate>& candidates,
                                   const DepthPeopleOptions& options = {});

// The depth people that no detection in `people` (located, base frame) already stands within `same_m` of.
std::vector<Detection> NotAlreadyFound(std::vector<Detection> depth_people, const std::vector<Detection>& people,
                                       double same_m = 0.5);

}  // namespace corridor::face
