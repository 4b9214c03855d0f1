// People near and far, standing, sideways and sitting, in the colour image: what a robot's camera sees of them. One
// detector alone sees too little: OpenCV's HOG (hog_people.h; Dalal and Triggs, CVPR 2005) finds whole upright bodies
// in full view and nobody cut by the frame, sitting or seen from a metre away. So this one also runs the cascades of
// Debian's opencv-data on the same grey image:
//   - head and shoulders (haarcascade_upperbody.xml; Kruppa, Castrillon-Santana and Schiele, "Fast and robust face
//     finding via local context", 2003): people near, sitting, or cut off below by the frame;
//   - faces turned to the camera (lbpcascade_frontalface_improved.xml) and to either side (haarcascade_profileface.xml,
//     searched in the mirrored image too for the other side): someone close whose body is hidden (behind a desk, a
//     board they hold).
// What the cascades find stands for the person around it: a head and shoulders box reaches down to the waist, a face
// box to the chest and a face's width to either side (clipped to the image), so that the box's depth and size at that
// depth (locate.h) are a person's. Finds that overlap (IoU over merge_iou, or the smaller mostly inside the larger) are
// one person: the larger box, the highest score, the source of the one that found it first in the order above.
// The cascades give no calibrated score: a find's score is that of its kind (*_score), under HOG's clear finds.
// Tuned on images of its own and evaluated on others (tests/data/detect/README.md, docs/benchmarks.md).
#pragma once

#include <filesystem>

#include <opencv2/objdetect.hpp>

#include "face/detect/detection.h"
#include "face/detect/hog_people.h"

namespace corridor::face {

struct PeopleOptions {
  HogOptions hog;
  bool upper_body = true;
  std::filesystem::path upper_body_cascade = "/usr/share/opencv4/haarcascades/haarcascade_upperbody.xml";
  int upper_body_neighbours = 6;
  int upper_body_min_px = 60;
  double upper_body_score = 0.5;
  bool faces = true;
  std::filesystem::path frontal_cascade = "/usr/share/opencv4/lbpcascades/lbpcascade_frontalface_improved.xml";
  std::filesystem::path profile_cascade = "/usr/share/opencv4/haarcascades/haarcascade_profileface.xml";
  int face_neighbours = 5;
  int face_min_px = 24;
  double face_score = 0.6;
  double cascade_scale_step = 1.1;
  double merge_iou = 0.3;
};

class PeopleDetector final : public Detector {
 public:
  // Throws std::invalid_argument if a cascade cannot be read, or for options out of range.
  explicit PeopleDetector(const PeopleOptions& options = {});
  std::vector<Detection> Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) override;
  std::string name() const override { return "people"; }

 private:
  // The cascade's finds in `gray` (equalized), at least min_px, with at least `neighbours`.
  std::vector<cv::Rect> Find(cv::CascadeClassifier& cascade, const cv::Mat& gray, int neighbours, int min_px) const;

  PeopleOptions options_;
  HogPeopleDetector hog_;
  cv::CascadeClassifier upper_body_;
  cv::CascadeClassifier frontal_;
  cv::CascadeClassifier profile_;
};

// Merges detections of one person (IoU over merge_iou, or the smaller box's area at least 60 % inside the larger's):
// the larger box and the highest score stay, with the source of the one listed first. Order: as found, best first.
std::vector<Detection> MergePeople(std::vector<Detection> found, double merge_iou);

}  // namespace corridor::face
