// The detection hook: what a detector finds in the robot's camera (people first), and the interface every detector
// implements. Detectors take a colour frame and the depth frame registered to it (same size and intrinsics, as the
// simulator's camera and a RealSense with its depth aligned to colour give them); a detection's 3D position comes
// from the depth inside its box (locate.h) and its track id from Tracker (tracker.h). Implementations: OpenCV's HOG
// people detector (hog_people.h, the default), the frontal face cascades (face_cascade.h), a user's model through
// cv::dnn (dnn_detector.h), and, in the simulator, the simulated people in view (simulated_people.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace corridor::face {

struct Detection {
  std::string label;                        // "person", "face", or a model's class
  double score = 0.0;                       // 0..1, the detector's confidence
  std::optional<cv::Rect2d> box;            // pixels of the colour image
  std::optional<Eigen::Vector3d> position;  // metres, base frame (x forward, y left, z up): the object's nearest
                                            // surface, at its middle
  int track_id = 0;                         // the same object from frame to frame; 0: not tracked
  std::string source;                       // "hog", "face_cascade", "dnn", "sim", or an external detector's name
  std::optional<double> bearing_rad{};      // its direction from the robot, base frame, counter-clockwise from ahead
};

class Detector {
 public:
  Detector() = default;
  Detector(const Detector&) = delete;
  Detector& operator=(const Detector&) = delete;
  virtual ~Detector() = default;

  // What the detector finds in one frame: `bgr` CV_8UC3, `depth_mm` CV_16UC1 of the same size (0: no depth; may be
  // empty when there is none). Boxes only; positions and track ids are added by the caller. Throws
  // std::invalid_argument for an image of the wrong type.
  virtual std::vector<Detection> Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) = 0;
  // Its name, as Detection::source.
  virtual std::string name() const = 0;
};

}  // namespace corridor::face
