// In the simulator, the simulated people in the camera's view stand in for a detector's output, as the simulated camera
// stands in for a real one: each person (an upright body of the crowd's radius and height, world frame) of whom at
// least a fifth projects into the image, within max_range_m, and who is not hidden (the depth frame at the middle of
// what is in view is not much nearer than they are) becomes a "person" with a box round what is in view and the
// position of their near surface, unless missed (miss_rate, seeded). What the daemon then does with it is exactly what
// it does with a real detector's.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "face/detect/detection.h"
#include "nav/geometry/camera_model.h"
#include "nav/geometry/pose2.h"

namespace corridor::face {

struct SimulatedPeopleOptions {
  double miss_rate = 0.1;  // the share of people in view not reported, at random
  double max_range_m = 6.0;
  double radius_m = 0.25;  // the crowd's (drivers/sim/crowd.h)
  double height_m = 1.7;
  double hidden_margin_m = 0.3;  // the depth at a person's middle this much nearer than them: hidden
  std::uint32_t seed = 1;
};

class SimulatedPeople {
 public:
  // Throws std::invalid_argument for a miss rate outside [0, 1] or sizes that are not positive.
  explicit SimulatedPeople(const SimulatedPeopleOptions& options = {});

  // The people at `people` (world frame, their centres on the floor) as the camera sees them with the robot at
  // world_T_base; `depth_mm` (the frame's, may be empty) hides those behind walls.
  std::vector<Detection> Detect(const std::vector<Eigen::Vector2d>& people, const nav::Pose2& world_T_base,
                                const cv::Mat& depth_mm, const nav::PinholeCamera& camera);

 private:
  SimulatedPeopleOptions options_;
  std::mt19937 random_;
};

}  // namespace corridor::face
