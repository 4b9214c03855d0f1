#include "face/detect/dnn_detector.h"

#include <fstream>
#include <stdexcept>

namespace corridor::face {
namespace {

std::vector<std::string> ReadClasses(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("dnn: cannot read the class list " + path.string());
  std::vector<std::string> classes;
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) classes.push_back(line);
  }
  if (classes.empty()) throw std::invalid_argument("dnn: the class list " + path.string() + " is empty");
  return classes;
}

}  // namespace

std::vector<Detection> ParseYoloOutput(const cv::Mat& output, const std::vector<std::string>& classes, cv::Size image,
                                       const DnnOptions& options) {
  // Rows of attributes: (cx, cy, w, h, [objectness,] scores...).
  cv::Mat rows = output.reshape(1, output.total() / static_cast<std::size_t>(output.size[output.dims - 1]));
  if (options.transposed) rows = rows.t();
  const int first_score = options.transposed ? 4 : 5;
  if (rows.cols != first_score + static_cast<int>(classes.size())) {
    throw std::invalid_argument("dnn: the output has " + std::to_string(rows.cols) + " values a box, expected " +
                                std::to_string(first_score + classes.size()) + " for " +
                                std::to_string(classes.size()) + " classes");
  }
  rows.convertTo(rows, CV_32F);
  const double sx = options.boxes_in_pixels ? static_cast<double>(image.width) / options.input_size_px : image.width;
  const double sy = options.boxes_in_pixels ? static_cast<double>(image.height) / options.input_size_px : image.height;
  std::vector<Detection> out;
  for (int r = 0; r < rows.rows; ++r) {
    const float* v = rows.ptr<float>(r);
    cv::Point best;
    double best_score = 0.0;
    cv::minMaxLoc(rows.row(r).colRange(first_score, rows.cols), nullptr, &best_score, nullptr, &best);
    const double score = best_score * (options.transposed ? 1.0 : v[4]);
    if (score < options.min_score) continue;
    const double w = v[2] * sx;
    const double h = v[3] * sy;
    out.push_back({classes[static_cast<std::size_t>(best.x)], score,
                   cv::Rect2d(v[0] * sx - w / 2.0, v[1] * sy - h / 2.0, w, h), std::nullopt, 0, "dnn"});
  }
  return out;
}

DnnDetector::DnnDetector(const DnnOptions& options) : options_(options), classes_(ReadClasses(options.classes)) {
  if (options.input_size_px < 32 || options.input_size_px % 32 != 0) {
    throw std::invalid_argument("dnn: input_size_px must be a multiple of 32");
  }
  try {
    net_ = cv::dnn::readNet(options.model.string(), options.config.string());
  } catch (const cv::Exception& e) {
    throw std::invalid_argument("dnn: cannot read the network " + options.model.string() + ": " + e.what());
  }
  if (net_.empty()) throw std::invalid_argument("dnn: cannot read the network " + options.model.string());
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
}

std::vector<Detection> DnnDetector::Detect(const cv::Mat& bgr, const cv::Mat& /*depth_mm*/) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("dnn: the colour image must be CV_8UC3");
  const cv::Mat blob = cv::dnn::blobFromImage(
      bgr, 1.0 / 255.0, cv::Size(options_.input_size_px, options_.input_size_px), cv::Scalar(), true, false);
  net_.setInput(blob);
  std::vector<cv::Mat> outputs;
  net_.forward(outputs, net_.getUnconnectedOutLayersNames());
  std::vector<Detection> all;
  for (const cv::Mat& o : outputs) {
    std::vector<Detection> part = ParseYoloOutput(o, classes_, bgr.size(), options_);
    all.insert(all.end(), part.begin(), part.end());
  }
  // Non-maximum suppression per class.
  std::vector<Detection> out;
  for (const std::string& label : classes_) {
    std::vector<cv::Rect2d> boxes;
    std::vector<float> scores;
    std::vector<const Detection*> of_label;
    for (const Detection& d : all) {
      if (d.label != label) continue;
      boxes.push_back(*d.box);
      scores.push_back(static_cast<float>(d.score));
      of_label.push_back(&d);
    }
    std::vector<int> kept;
    cv::dnn::NMSBoxes(boxes, scores, static_cast<float>(options_.min_score), static_cast<float>(options_.nms_iou),
                      kept);
    for (int i : kept) out.push_back(*of_label[static_cast<std::size_t>(i)]);
  }
  return out;
}

}  // namespace corridor::face
