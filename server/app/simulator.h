// The built-in simulator as the configuration describes it (sim.*): the world with its obstacles and people, and the
// robot at its start; and the map the daemon starts in.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>

#include "drivers/sim/sim_robot.h"
#include "drivers/sim/world.h"
#include "server/app/graph.h"
#include "server/config/config.h"
#include "server/fleet/doors.h"
#include "server/fleet/lifts.h"

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

// The simulator's lifts as the building's lift controller, for a simulated building whose configuration names no
// controller of its own (building.controller): calls and releases move the simulated cars at once, as a controller that
// always takes the robot would, and their state is the simulator's. Answers on the io executor, as a real one's do.
class SimLiftController final : public LiftController {
 public:
  SimLiftController(boost::asio::io_context& io, drivers::sim::SimRobot& sim) : io_(io), sim_(sim) {}
  void Call(const std::string& lift, const std::string& floor, Done done) override;
  void State(const std::string& lift, Done done) override;
  void Release(const std::string& lift) override;

 private:
  boost::asio::io_context& io_;
  drivers::sim::SimRobot& sim_;
};

// The simulator's doors as the building's door controller, for a simulated world with doors whose configuration names
// no controller (doors.controller): a door asked to open swings open kDoorOpenS of simulated time later, so the robot
// waits for it as it would for a real one; released, a door it opened closes (one the world has open stays open). A
// door the simulator does not have is refused. Answers on the io executor, as a real controller's do.
class SimDoorController final : public DoorController {
 public:
  static constexpr double kDoorOpenS = 2.0;
  SimDoorController(boost::asio::io_context& io, drivers::sim::SimRobot& sim) : io_(io), sim_(sim) {}
  void Open(const std::string& door, Done done) override;
  void State(const std::string& door, Done done) override;
  void Release(const std::string& door) override;

 private:
  std::optional<bool> IsOpen(const std::string& door) const;  // nullopt: the simulator has no such door
  void Answer(Done done, nav::DoorReport report);

  boost::asio::io_context& io_;
  drivers::sim::SimRobot& sim_;
  std::map<std::string, drivers::TimeNs> asked_;  // the doors asked open and closed then, and when
};

}  // namespace corridor::server
