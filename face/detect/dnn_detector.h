// A detector the user supplies: a YOLO-family network read by OpenCV's dnn module from an ONNX file or a Darknet
// .cfg + .weights pair (DPoom ran tiny-YOLO), with its class names one per line. None is shipped: the path is the
// user's (perception.dnn in the configuration). Outputs are read in the two layouts these networks use: rows of
// (cx, cy, w, h, objectness, class scores...) (Darknet, YOLOv5), or, with `transposed`, columns of (cx, cy, w, h,
// class scores...) without objectness (YOLOv8); overlapping boxes of a class are merged by non-maximum suppression.
#pragma once

#include <filesystem>

#include <opencv2/dnn.hpp>

#include "face/detect/detection.h"

namespace corridor::face {

struct DnnOptions {
  std::filesystem::path model;    // .onnx, or a Darknet .weights
  std::filesystem::path config;   // a Darknet .cfg (empty for ONNX)
  std::filesystem::path classes;  // class names, one per line, in the network's order
  int input_size_px = 416;        // the network's square input
  bool transposed = false;        // YOLOv8's output layout
  bool boxes_in_pixels = false;   // boxes in input pixels (YOLOv5/v8 ONNX) rather than fractions (Darknet)
  double min_score = 0.4;
  double nms_iou = 0.45;
};

class DnnDetector final : public Detector {
 public:
  // Throws std::invalid_argument with the path when the network or the class list cannot be read.
  explicit DnnDetector(const DnnOptions& options);
  std::vector<Detection> Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) override;
  std::string name() const override { return "dnn"; }

 private:
  DnnOptions options_;
  std::vector<std::string> classes_;
  cv::dnn::Net net_;
};

// The detections in one output blob of a YOLO-family network (its rows, or columns when transposed, as DnnOptions
// says) for an image of `image` size: boxes scaled to the image, scores of at least min_score, before suppression.
// Throws std::invalid_argument for a blob whose width does not fit the class count.
std::vector<Detection> ParseYoloOutput(const cv::Mat& output, const std::vector<std::string>& classes, cv::Size image,
                                       const DnnOptions& options);

}  // namespace corridor::face
