// What the people the robot detects mean for its face and manners (pure): someone near in front, someone in its way,
// someone looking at it, and where the eyes should look.
//   near:     a person ahead (within ahead_half_angle_rad) within near_m
//   blocking: a person ahead within blocking_m and blocking_half_angle_rad: in the robot's way
//   looking:  a face turned to the robot within looking_m (the face cascade), or a person who has stood still within
//             near_m ahead for standing_s (turned to the robot, as far as a body detector can tell)
//   gaze:     the bearing of the nearest person within gaze_m; without one, the way the robot is turning
#pragma once

#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "drivers/clock.h"
#include "face/detect/detection.h"

namespace corridor::face {

struct SocialOptions {
  double near_m = 1.5;
  double ahead_half_angle_rad = 0.7854;
  double blocking_m = 1.0;
  double blocking_half_angle_rad = 0.5236;
  double looking_m = 2.5;
  double standing_s = 2.0;
  double standing_radius_m = 0.25;  // a person who stayed within this of where they were is standing
  double gaze_m = 4.0;
  double max_gaze_rad = 0.7;  // the eyes turn at most this far either way
};

struct SocialCues {
  bool near = false;
  bool blocking = false;
  bool looking = false;
  double gaze_rad = 0.0;  // where the eyes look, from straight ahead, counter-clockwise (left)
  bool gaze_at_person = false;
};

class SocialSense {
 public:
  explicit SocialSense(const SocialOptions& options = {}) : options_(options) {}

  // The cues from this sample's detections (base frame), with the robot turning at turn_rps and driving at speed_mps.
  // Call with non-decreasing times.
  SocialCues Update(const std::vector<Detection>& detections, double speed_mps, double turn_rps,
                    drivers::TimeNs now_ns);

 private:
  struct Standing {
    Eigen::Vector2d where = Eigen::Vector2d::Zero();
    drivers::TimeNs since_ns = 0;
    drivers::TimeNs seen_ns = 0;
  };
  SocialOptions options_;
  std::map<int, Standing> standing_;  // by track id: where each person was when they stopped moving
};

}  // namespace corridor::face
