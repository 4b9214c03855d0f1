// Frontal faces by a boosted cascade from Debian's opencv-data (/usr/share/opencv4): Viola and Jones' Haar cascade
// (haarcascade_frontalface_default.xml) or the faster LBP one (lbpcascade_frontalface_improved.xml). A face turned to
// the camera at close range is a person looking at the robot: the face greets them and looks at them.
#pragma once

#include <filesystem>

#include <opencv2/objdetect.hpp>

#include "face/detect/detection.h"

namespace corridor::face {

struct FaceCascadeOptions {
  std::filesystem::path cascade = "/usr/share/opencv4/lbpcascades/lbpcascade_frontalface_improved.xml";
  double scale_step = 1.1;
  int min_neighbours = 4;
  int min_size_px = 24;  // faces smaller than this are not searched for (a 16 cm face at about 3.5 m at 525 px)
};

class FaceCascadeDetector final : public Detector {
 public:
  // Throws std::invalid_argument if the cascade cannot be read, or for options out of range.
  explicit FaceCascadeDetector(const FaceCascadeOptions& options = {});
  std::vector<Detection> Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) override;
  std::string name() const override { return "face_cascade"; }

 private:
  FaceCascadeOptions options_;
  cv::CascadeClassifier cascade_;
};

}  // namespace corridor::face
