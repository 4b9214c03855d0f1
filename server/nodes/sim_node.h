// Runs the simulator. With threads (corridord) a timer on the sim executor steps the simulated robot until simulated
// time catches up with the wall clock; in lockstep the graph's owner calls Step, and the graph's clock is the
// simulator's own (server/app/graph.h). Either way the SimRobot's sensors publish through the driver bridge as real
// devices would, and the node publishes the simulator's ground truth (the robot's pose, the people) for the console.
#pragma once

#include <memory>

#include "drivers/sim/sim_robot.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/store/saved_pose.h"

namespace corridor::server {

class SimNode final : public Node {
 public:
  // pose_file: where the simulated robot's true pose is saved (as `world`'s) whenever it moved 0.1 m or 5 degrees, so
  // that a restart finds it where it stopped (MakeSimulator); empty: nowhere.
  // `floors`: a building's floors side by side in the world: the truth is published in the map frame of the floor the
  // robot is on (null: the world's frame is the map's).
  SimNode(Executor& executor, Bus& bus, drivers::sim::SimRobot& robot, std::filesystem::path pose_file = {},
          std::string world = {}, std::shared_ptr<const drivers::sim::Floors> floors = nullptr);
  void Activate() override;
  void Deactivate() override;
  // Saves the robot's true pose, however little it moved since the last save (the executors have stopped).
  void Cleanup() override;
  // Lockstep: one physics step, on the caller's thread, and the ground truth after it.
  void Step();

 private:
  void KeepUp();  // threads: steps until simulated time has caught up with the wall clock
  void PublishTruth();

  drivers::sim::SimRobot& robot_;
  std::unique_ptr<PeriodicTimer> timer_;
  LoopStats& loop_;
  drivers::TimeNs wall_start_ns_ = 0;
  drivers::TimeNs sim_start_ns_ = 0;
  bool has_pedestrians_ = false;
  std::filesystem::path pose_file_;
  std::string world_;
  std::shared_ptr<const drivers::sim::Floors> floors_;
  std::optional<SavedPose> saved_;
};

}  // namespace corridor::server
