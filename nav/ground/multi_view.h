// Step 5 of corridor's multi-baseline multi-view filter (MMSVF, docs/asns.md; steps 1-4, the two baselines, are
// drivers/stereo/multi_baseline.h): a stereo camera's depth reading is kept when the 3D cell it falls in was seen in
// enough of the last frames, each placed where the robot's odometry says it was taken ("multi-view"). A surface lands
// in the same cells frame after frame; a mismatch of the matcher lands where the images' noise puts it, a different
// cell each time. Readings nearer than from_m pass unchanged: near, disparities are large and trusted, and what comes
// close (a person walking in) must not wait a frame. A cell counts the views of the six cells beside it too: a surface
// that lies along the cells' boundary falls on either side of it from frame to frame.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct MultiViewOptions {
  bool enabled = false;  // on for a stereo camera (the graph filters its frames before anything reads them)
  double cell_m = 0.1;   // the cells' side, in the odometry frame
  int views = 2;         // a reading is kept when its cell was seen in this many of the last `window` frames (this one
  int window = 3;        //   included): at 15 frames a second, a new obstacle shows one frame later
  double from_m = 1.0;   // nearer readings are not filtered
};

// Throws std::invalid_argument naming the option when `options` cannot work.
void ValidateMultiViewOptions(const MultiViewOptions& options);

class MultiViewFilter {
 public:
  // Frames of `camera` (its size and mounting). Throws std::invalid_argument for bad options or a camera without size.
  MultiViewFilter(const PinholeCamera& camera, const MultiViewOptions& options);

  // Zeroes the readings of `depth_mm` (CV_16UC1 millimetres, the camera's size) whose cells were not seen often enough,
  // the frame taken with the robot at `odom_T_base` and the camera at `base_T_camera` (none: as mounted; a pan servo
  // turns it); returns how many were zeroed. Frames in the order taken.
  int Apply(cv::Mat& depth_mm, const Pose2& odom_T_base,
            const std::optional<Eigen::Isometry3d>& base_T_camera = std::nullopt);

  std::size_t cells() const { return cells_.size(); }

 private:
  struct Cell {
    std::uint64_t key = 0;
    std::uint32_t seen = 0;  // bit i: seen i frames before `frame`
    std::int64_t frame = 0;
    std::int64_t judged = 0;  // the frame `keep` was found in
    bool keep = false;
  };
  // The views of `cell` and the cells beside it, within the window (the cell itself seen in this frame).
  bool Keep(Cell& cell);

  PinholeCamera camera_;
  MultiViewOptions options_;
  std::uint32_t window_mask_;
  std::vector<Eigen::Vector3f> rays_;  // each pixel's ray in the camera frame, z = 1
  // This frame's cell of each pixel (null: no reading, or not filtered). An unordered_map's elements stay where they
  // are when it grows, so the pointers hold until cells are erased after the frame.
  std::vector<Cell*> pixel_cells_;
  std::unordered_map<std::uint64_t, Cell> cells_;
  std::int64_t frame_ = 0;
};

}  // namespace corridor::nav
