// For tests: a BGR image written as a V4L2 YUYV buffer (BT.601, video range; each pair of pixels sharing their mean
// chroma), as a UVC camera sends it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace corridor::testing {

inline std::vector<std::uint8_t> ToYuyv(const cv::Mat& bgr) {
  std::vector<std::uint8_t> yuyv(static_cast<std::size_t>(bgr.cols) * bgr.rows * 2);
  const auto clamp = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c + 1 < bgr.cols; c += 2) {
      double y[2];
      double u = 0.0;
      double v = 0.0;
      for (int k = 0; k < 2; ++k) {
        const cv::Vec3b p = bgr.at<cv::Vec3b>(r, c + k);
        const double red = p[2], green = p[1], blue = p[0];
        y[k] = 16 + 0.257 * red + 0.504 * green + 0.098 * blue;
        u += 0.5 * (128 - 0.148 * red - 0.291 * green + 0.439 * blue);
        v += 0.5 * (128 + 0.439 * red - 0.368 * green - 0.071 * blue);
      }
      std::uint8_t* at = &yuyv[(static_cast<std::size_t>(r) * bgr.cols + c) * 2];
      at[0] = clamp(y[0]);
      at[1] = clamp(u);
      at[2] = clamp(y[1]);
      at[3] = clamp(v);
    }
  }
  return yuyv;
}

}  // namespace corridor::testing
