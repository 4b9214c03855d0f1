// The simulated charging dock: a box standing on the floor whose face is where nav::DockGeometry says, seen by the
// camera and the laser, solid to the robot (exactly: the collision grid's cells are too coarse to dock against), and
// with charging contacts that connect while the robot stands within contact_m and contact_rad of its docked pose.
#pragma once

#include "drivers/sim/diff_drive_sim.h"
#include "drivers/sim/world.h"
#include "nav/geometry/pose2.h"
#include "nav/mission/docking.h"

namespace corridor::drivers::sim {

struct SimDockOptions {
  nav::Pose2 pose;  // the robot's docked pose (world frame), facing the dock
  nav::DockGeometry geometry;
  double depth_m = 0.12;  // of the box, behind its face
  double height_m = 0.25;
  double contact_m = 0.03;      // the contacts connect within this of the docked pose...
  double contact_rad = 0.0873;  // ...and this of its heading (5 degrees)
};

class SimDock {
 public:
  explicit SimDock(const SimDockOptions& options);

  const SimDockOptions& options() const { return options_; }
  const Block& block() const { return block_; }
  // The box, for the camera and the laser.
  TriangleMesh Mesh() const;
  bool Contacts(const nav::Pose2& robot) const;

 private:
  SimDockOptions options_;
  Block block_;
};

// Adds the dock's box to the world's mesh (the camera and the laser see it; the robot's SimRobot keeps it solid).
void AddDock(World& world, const SimDock& dock);

}  // namespace corridor::drivers::sim
