// A reader of a camera's depth frames (DepthScan, Morp, Afds, VoxelObstacles) whose precomputed geometry - its rays
// in the base frame, its lanes projected into the image - holds for one pose of the camera: built anew when a frame
// comes from another pose (a camera on a pan servo, nav::PanTurn), kept while the camera stays where it is. While
// the camera turns, MORP and the obstacle memory's depth scan cost 3-4 times their reading of a still camera's frame
// (bench/ground_bench BM_PannedFrame: 0.25 ms a frame against 0.08 at 320 x 240, 0.75 against 0.21 at 640 x 480, one
// core), and nothing more once it stops.
#pragma once

#include <functional>
#include <optional>
#include <utility>

#include <Eigen/Geometry>

#include "nav/geometry/camera_model.h"

namespace corridor::nav {

template <typename Reader>
class Posed {
 public:
  // Builds a reader for a camera (its constructor's other arguments bound in), e.g.
  //   [options](std::optional<DepthScan>& r, const PinholeCamera& c) { r.emplace(c, options); }
  using Build = std::function<void(std::optional<Reader>& reader, const PinholeCamera& camera)>;

  Posed() = default;  // no reader until Reset
  Posed(const Posed&) = delete;
  Posed& operator=(const Posed&) = delete;

  // The reader for `camera` at rest. Throws what the reader's constructor throws (for a camera or options that cannot
  // work).
  void Reset(const PinholeCamera& camera, Build build) {
    camera_ = camera;
    build_ = std::move(build);
    build_(reader_, camera_);
  }

  // The reader for a frame taken with the camera at `base_T_camera` (none: where it was for the frame before).
  Reader& At(const std::optional<Eigen::Isometry3d>& base_T_camera) {
    if (base_T_camera && Moved(*base_T_camera, camera_.base_T_camera)) {
      camera_.base_T_camera = *base_T_camera;
      build_(reader_, camera_);
    }
    return *reader_;
  }

  explicit operator bool() const { return reader_.has_value(); }
  Reader* operator->() { return &*reader_; }
  const Reader* operator->() const { return &*reader_; }
  // The camera at the pose the reader is built for.
  const PinholeCamera& camera() const { return camera_; }

 private:
  PinholeCamera camera_;
  Build build_;
  std::optional<Reader> reader_;
};

}  // namespace corridor::nav
