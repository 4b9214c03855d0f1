// The lanes of a robot without a depth camera (a TurtleBot 3 Burger: a base and a 2D laser), from its laser's scan:
// the same lanes as MORP's (nav/ground/morp.h, LaneOffsets), each free up to the nearest point the laser hit on its
// line ahead of the robot (LaneOnLine), so that the local policy and the command gate read a laser robot as they read
// a camera robot. What passes between two lines (a table leg of a few centimetres) is missed by both, as by MORP: the
// obstacle memory, fed with every hit, keeps the robot off it.
//
// A laser sees one plane at its height: what stands lower (a step, a cable, a dog) or higher (a table top) is not
// seen, and a lane with no hit in it is free out to max_range_m. What is nearer than the laser's minimum range gives
// no return and looks free too; the base's bumper is then the last word.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "nav/ground/morp.h"

namespace corridor::nav {

class LaserLanes {
 public:
  // `options`: the lanes' layout (lanes, span_m, lane_width_m) and max_range_m; `height_m`: the laser's height above
  // the floor (where its dead-ends are). Throws std::invalid_argument for non-positive widths or range.
  LaserLanes(const MorpOptions& options, double height_m);

  // The lanes for one scan's hits (base frame, x forward, y left). Allocation-free after the first call.
  const std::vector<LaneResult>& Process(std::span<const Eigen::Vector2f> hits);

  int lane_count() const { return static_cast<int>(results_.size()); }

 private:
  MorpOptions options_;
  double height_m_;
  std::vector<double> offsets_;  // left to right
  std::vector<LaneResult> results_;
};

}  // namespace corridor::nav
