// For tests and benchmarks: the layers of an nav::Mlp built in OpenCV's dnn module from the same weights (its
// InnerProduct layers and activations), the second implementation the network core is checked and timed against.
#pragma once

#include <string>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include "nav/learning/mlp.h"

namespace corridor::testing {

inline cv::dnn::Net OpenCvMlp(const nav::Mlp& mlp) {
  cv::dnn::Net net;
  int index = 0;
  for (const nav::DenseLayer& layer : mlp.layers()) {
    cv::dnn::LayerParams dense;
    dense.set("num_output", static_cast<int>(layer.weights.rows()));
    dense.set("bias_term", true);
    cv::Mat weights(static_cast<int>(layer.weights.rows()), static_cast<int>(layer.weights.cols()), CV_32F);
    for (int r = 0; r < weights.rows; ++r) {
      for (int c = 0; c < weights.cols; ++c) weights.at<float>(r, c) = layer.weights(r, c);
    }
    cv::Mat bias(1, static_cast<int>(layer.bias.size()), CV_32F);
    for (int c = 0; c < bias.cols; ++c) bias.at<float>(0, c) = layer.bias(c);
    dense.blobs = {weights, bias};
    const std::string name = "layer" + std::to_string(index++);
    net.addLayerToPrev(name, "InnerProduct", dense);
    const char* type = nullptr;
    switch (layer.activation) {
      case nav::Activation::kIdentity: break;
      case nav::Activation::kRelu: type = "ReLU"; break;
      case nav::Activation::kTanh: type = "TanH"; break;
      case nav::Activation::kSigmoid: type = "Sigmoid"; break;
      case nav::Activation::kSoftmax: type = "Softmax"; break;
    }
    if (type != nullptr) {
      cv::dnn::LayerParams activation;
      net.addLayerToPrev(name + "_" + type, type, activation);
    }
  }
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  return net;
}

}  // namespace corridor::testing
