// For the stereo camera's tests and benches: a room of textured walls with boxes of several heights on its floor, and
// poses across it from which the simulated camera sees floor, walls and boxes from 0.3 to 5 m; and one box alone on a
// large floor.
#pragma once

#include <Eigen/Geometry>

#include "drivers/sim/world.h"

namespace corridor::testing {

inline drivers::sim::TriangleMesh StereoRoom() {
  drivers::sim::TriangleMesh mesh;
  mesh.AddBox({-2.0f, -6.0f, -0.1f}, {12.0f, 6.0f, 0.0f}, {0.55f, 0.5f, 0.45f});  // floor
  mesh.AddBox({6.0f, -6.0f, 0.0f}, {6.2f, 6.0f, 2.5f}, {0.7f, 0.7f, 0.7f});
  mesh.AddBox({-2.0f, 2.0f, 0.0f}, {6.0f, 2.2f, 2.5f}, {0.6f, 0.65f, 0.7f});
  mesh.AddBox({-2.0f, -2.2f, 0.0f}, {6.0f, -2.0f, 2.5f}, {0.6f, 0.65f, 0.7f});
  for (int i = 0; i < 8; ++i) {
    const float x = 0.8f + 0.6f * static_cast<float>(i);
    const float y = -1.5f + 0.4f * static_cast<float>((i * 5) % 8);
    const float height = 0.3f + 0.1f * static_cast<float>(i % 4);
    mesh.AddBox({x, y, 0.0f}, {x + 0.3f, y + 0.3f, height}, {0.3f + 0.05f * static_cast<float>(i), 0.4f, 0.5f});
  }
  return mesh;
}

// The n-th of `count` poses of the robot's base, walking diagonally across the room while turning from 34 degrees
// right to 34 degrees left.
inline Eigen::Isometry3d StereoRoomPose(int n, int count) {
  const double s = count > 1 ? static_cast<double>(n) / (count - 1) : 0.0;
  Eigen::Isometry3d pose(Eigen::AngleAxisd(-0.6 + 1.08 * s, Eigen::Vector3d::UnitZ()));
  pose.translation() = Eigen::Vector3d(-1.0 + 1.8 * s, -0.8 + 1.44 * s, 0.0);
  return pose;
}

// A box 40 cm deep, `half_width_m` either side of the x axis and `height_m` high, alone on a floor 55 x 20 m, its face
// `distance_m` from the simulator's default camera on a robot at the origin (the camera is 0.1 m ahead of its centre).
inline drivers::sim::TriangleMesh BoxAhead(float distance_m, float half_width_m, float height_m) {
  drivers::sim::TriangleMesh mesh;
  mesh.AddBox({-5.0f, -10.0f, -0.01f}, {50.0f, 10.0f, 0.0f}, {0.6f, 0.6f, 0.6f});
  mesh.AddBox({distance_m + 0.1f, -half_width_m, 0.0f}, {distance_m + 0.5f, half_width_m, height_m},
              {0.5f, 0.35f, 0.2f});
  return mesh;
}

}  // namespace corridor::testing
