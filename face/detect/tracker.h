// Track ids that stay with the same object from frame to frame: a detection takes the id of the track of its label
// whose last position (world frame) is nearest within gate_m, or, without a position, whose last box overlaps its box
// most (IoU at least min_iou); each track takes at most one detection a frame; the others start new tracks. A track
// not seen for forget_s is forgotten. Positions are compared in the world frame, so that the robot's own motion does
// not break a track.
#pragma once

#include <vector>

#include "drivers/clock.h"
#include "face/detect/detection.h"
#include "nav/geometry/pose2.h"

namespace corridor::face {

struct TrackerOptions {
  double gate_m = 0.8;
  double min_iou = 0.3;
  double forget_s = 1.5;
};

class Tracker {
 public:
  explicit Tracker(const TrackerOptions& options = {}) : options_(options) {}

  // Gives each of `detections` (taken at now_ns with the robot at world_T_base) a track id.
  void Assign(std::vector<Detection>& detections, const nav::Pose2& world_T_base, drivers::TimeNs now_ns);

 private:
  struct Track {
    int id = 0;
    std::string label;
    std::optional<Eigen::Vector2d> position;  // world frame
    std::optional<cv::Rect2d> box;
    drivers::TimeNs seen_ns = 0;
  };

  TrackerOptions options_;
  std::vector<Track> tracks_;
  int next_id_ = 1;
};

// Intersection over union of two boxes; 0 when either is empty.
double IntersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b);

}  // namespace corridor::face
