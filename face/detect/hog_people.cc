#include "face/detect/hog_people.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace corridor::face {

HogPeopleDetector::HogPeopleDetector(const HogOptions& options) : options_(options) {
  if (!(options.upscale >= 1.0 && options.upscale <= 4.0) || !(options.scale_step > 1.0) ||
      options.window_stride_px < 1 || options.padding_px < 0 || options.group_threshold < 0) {
    throw std::invalid_argument("hog: upscale within [1, 4], scale_step > 1, window_stride_px >= 1");
  }
  hog_.setSVMDetector(cv::HOGDescriptor::getDefaultPeopleDetector());
}

std::vector<Detection> HogPeopleDetector::Detect(const cv::Mat& bgr, const cv::Mat& /*depth_mm*/) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("hog: the colour image must be CV_8UC3");
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  if (options_.upscale > 1.0) cv::resize(gray, gray, {}, options_.upscale, options_.upscale, cv::INTER_LINEAR);
  std::vector<cv::Rect> found;
  std::vector<double> weights;
  const cv::Size stride(options_.window_stride_px, options_.window_stride_px);
  const cv::Size padding(options_.padding_px, options_.padding_px);
  hog_.detectMultiScale(gray, found, weights, options_.hit_threshold, stride, padding, options_.scale_step,
                        static_cast<double>(options_.group_threshold));
  std::vector<Detection> out;
  for (std::size_t i = 0; i < found.size(); ++i) {
    // The SVM's margin (0 at the threshold, 1-3 for clear people) as a score in [0, 1).
    const double score = i < weights.size() ? 1.0 - std::exp(-std::max(0.0, weights[i])) : 0.5;
    if (score < options_.min_score) continue;
    // The person within the window: Dalal and Triggs' 64 x 128 windows hold a 32 x 96 person with a 16-pixel margin.
    const cv::Rect& r = found[i];
    const double k = 1.0 / options_.upscale;
    const cv::Rect2d person((r.x + r.width * 0.25) * k, (r.y + r.height * 0.125) * k, r.width * 0.5 * k,
                            r.height * 0.75 * k);
    out.push_back({"person", score, person, std::nullopt, 0, name()});
  }
  return out;
}

}  // namespace corridor::face
