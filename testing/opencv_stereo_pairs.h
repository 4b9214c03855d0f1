// For tests: Debian's opencv-doc (./dev installs it) holds 13 real pairs of 640 x 480 views of a 9 x 6 board of 25 mm
// squares taken by a side-by-side stereo camera, and the intrinsics OpenCV's own samples calibrated from them
// (intrinsics.yml: its stereo sample; left_intrinsics.yml: its single-camera sample, the left camera).
#pragma once

#include <cstdio>
#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace corridor::testing {

inline const std::filesystem::path kOpenCvData = "/usr/share/doc/opencv-doc/examples/data";

struct StereoViews {
  std::vector<cv::Mat> left, right;  // grey; empty where a file is missing
};

// The 13 pairs (left01/right01 ... left14/right14; the set has no 10), read once.
inline const StereoViews& OpenCvStereoPairs() {
  static const StereoViews views = [] {
    StereoViews v;
    for (int n : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
      char left[16];
      char right[16];
      std::snprintf(left, sizeof left, "left%02d.jpg", n);
      std::snprintf(right, sizeof right, "right%02d.jpg", n);
      v.left.push_back(cv::imread((kOpenCvData / left).string(), cv::IMREAD_GRAYSCALE));
      v.right.push_back(cv::imread((kOpenCvData / right).string(), cv::IMREAD_GRAYSCALE));
    }
    return v;
  }();
  return views;
}

}  // namespace corridor::testing
