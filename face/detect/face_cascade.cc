#include "face/detect/face_cascade.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace corridor::face {

FaceCascadeDetector::FaceCascadeDetector(const FaceCascadeOptions& options) : options_(options) {
  if (!(options.scale_step > 1.0) || options.min_neighbours < 0 || options.min_size_px < 8) {
    throw std::invalid_argument("face cascade: scale_step > 1, min_neighbours >= 0, min_size_px >= 8");
  }
  if (!cascade_.load(options.cascade.string())) {
    throw std::invalid_argument("face cascade: cannot read " + options.cascade.string() +
                                " (Debian's opencv-data has the cascades)");
  }
}

std::vector<Detection> FaceCascadeDetector::Detect(const cv::Mat& bgr, const cv::Mat& /*depth_mm*/) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("face cascade: the colour image must be CV_8UC3");
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::equalizeHist(gray, gray);
  std::vector<cv::Rect> found;
  std::vector<int> levels;
  std::vector<double> weights;
  cascade_.detectMultiScale(gray, found, levels, weights, options_.scale_step, options_.min_neighbours, 0,
                            cv::Size(options_.min_size_px, options_.min_size_px), cv::Size(), true);
  std::vector<Detection> out;
  for (std::size_t i = 0; i < found.size(); ++i) {
    // The last stage's sum (about 0 at the threshold, a few for clear faces) as a score in (0, 1).
    const double w = i < weights.size() ? weights[i] : 0.0;
    const double score = 1.0 / (1.0 + std::exp(-w));
    out.push_back({"face", score, cv::Rect2d(found[i]), std::nullopt, 0, name()});
  }
  return out;
}

}  // namespace corridor::face
