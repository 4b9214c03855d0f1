// People by OpenCV's HOG detector with its built-in linear SVM (Dalal and Triggs, "Histograms of oriented gradients
// for human detection", CVPR 2005; cv::HOGDescriptor::getDefaultPeopleDetector): whole, upright bodies in a
// 64 x 128 window, searched over scales. The boxes are the person's extent in the window (its middle half across and
// three quarters down: the windows hold a 32 x 96 person with a 16-pixel margin), so a person must be about 96 px
// tall to be found; `upscale` enlarges the image first for smaller ones (at the square of its cost).
#pragma once

#include <opencv2/objdetect.hpp>

#include "face/detect/detection.h"

namespace corridor::face {

struct HogOptions {
  double upscale = 1.0;        // the image is enlarged by this before the search (>= 1)
  double scale_step = 1.2;     // between the pyramid's levels
  int window_stride_px = 8;    // of the search, in the (enlarged) image
  int padding_px = 32;         // windows may reach this far past the image's edges (people cut by the frame)
  double hit_threshold = 0.0;  // the SVM's margin a window needs
  int group_threshold = 2;     // overlapping windows needed to make a detection
  double min_score = 0.3;      // detections scoring less are dropped
};

class HogPeopleDetector final : public Detector {
 public:
  // Throws std::invalid_argument for options out of range.
  explicit HogPeopleDetector(const HogOptions& options = {});
  std::vector<Detection> Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) override;
  std::string name() const override { return "hog"; }

 private:
  HogOptions options_;
  cv::HOGDescriptor hog_;
};

}  // namespace corridor::face
