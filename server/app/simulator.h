// The built-in simulator as the configuration describes it (sim.*): the world with its obstacles and people, and the
// robot at its start; and the map the daemon starts in.
#pragma once

#include <memory>

#include "drivers/sim/sim_robot.h"
#include "drivers/sim/world.h"
#include "server/app/graph.h"
#include "server/runtime/config.h"

namespace corridor::server {

struct Simulator {
  std::shared_ptr<const drivers::sim::World> world;
  std::unique_ptr<drivers::sim::SimRobot> robot;
  std::shared_ptr<const drivers::sim::Floors> floors;  // a building's floors side by side; null: one floor

  // The simulated robot as the graph's devices (with its laser when devices.laser.driver is sim).
  Devices devices(const Config& config) const;
};

// Throws std::runtime_error when the world cannot be loaded or the robot's start overlaps an obstacle. The robot starts
// where the last run left it in the same world (SimPoseFile) when that pose is free, else at sim.start.
Simulator MakeSimulator(const Config& config);

// Where the simulated robot's true pose is kept across restarts.
std::filesystem::path SimPoseFile(const Config& config);

// The simulated world's name, as the saved pose records it.
std::string SimWorldName(const Config& config);

// With a building, the map of the floor the robot was last localized on (the first floor's at first); else the
// configured map file, else the simulator's world when it is a map, else the world's collision slice (what the robot
// can bump into). Throws when there is neither a map nor a world.
NamedMap InitialMap(const Config& config, const drivers::sim::World* world);

}  // namespace corridor::server
