// A simulated door: a panel across a passage that the building's door controller opens and closes. Closed, it is
// solid to the robot (an exact rectangle, like the dock) and seen by the camera and the laser (a box among the moving
// geometry, so it can vanish when it opens); open, it is gone. What asks it to open is the door controller's business
// (server/fleet/doors.h); the simulator only moves it.
#pragma once

#include <string>

#include <Eigen/Core>

#include "drivers/sim/diff_drive_sim.h"
#include "drivers/sim/world.h"

namespace corridor::drivers::sim {

struct SimDoorOptions {
  std::string id;
  Eigen::Vector2d from = Eigen::Vector2d::Zero();  // the panel's line across the passage (world frame)
  Eigen::Vector2d to = Eigen::Vector2d::Zero();
  double thickness_m = 0.06;
  double height_m = 2.0;
  bool open = false;  // at start
};

class SimDoor {
 public:
  explicit SimDoor(const SimDoorOptions& options);

  const SimDoorOptions& options() const { return options_; }
  const std::string& id() const { return options_.id; }
  bool open() const { return open_; }
  void set_open(bool open) { open_ = open; }
  const Block& block() const { return block_; }
  // The closed panel, for the camera and the laser.
  TriangleMesh Mesh() const;

 private:
  SimDoorOptions options_;
  Block block_;
  bool open_ = false;
};

}  // namespace corridor::drivers::sim
