#include "server/app/simulator.h"

#include <spdlog/spdlog.h>

#include <random>

#include "nav/map/map_io.h"
#include "server/store/saved_pose.h"

namespace corridor::server {

Devices Simulator::devices(const Config& config) const {
  return Devices{*robot, *robot, config.sim.robot.laser.enabled ? robot.get() : nullptr, robot.get(), robot.get()};
}

std::filesystem::path SimPoseFile(const Config& config) { return config.store.state_dir / "sim_pose.json"; }

Simulator MakeSimulator(const Config& config) {
  Simulator sim;
  sim.world = [&] {
    drivers::sim::World w = drivers::sim::LoadWorld(config.sim.world, config.sim.world_options);
    drivers::sim::AddObstacles(w, config.sim.obstacles);  // in the world, not in its map
    if (config.sim.robot.dock) drivers::sim::AddDock(w, drivers::sim::SimDock(*config.sim.robot.dock));
    return std::make_shared<const drivers::sim::World>(std::move(w));
  }();
  nav::Pose2 start = config.sim.robot.start;
  if (const std::optional<SavedPose> saved = LoadSavedPose(SimPoseFile(config));
      saved && saved->place == config.sim.world.string()) {
    const drivers::sim::DiffDriveSim probe(sim.world->collision, config.sim.robot.base, saved->pose);
    if (probe.Collides(saved->pose)) {
      spdlog::warn("simulator: the robot's saved pose overlaps something now; starting at sim.start");
    } else {
      start = saved->pose;
      spdlog::info("simulator: the robot is where the last run left it: ({:.2f}, {:.2f})", start.x_m, start.y_m);
    }
  }
  drivers::sim::SimOptions options = config.sim.robot;
  options.start = start;
  if (config.sim.pedestrians > 0) {
    std::mt19937 rng(config.sim.robot.seed);
    drivers::sim::RouteArea area;
    area.center = start.translation();
    area.within_m = config.sim.pedestrians_within_m;
    area.clearance_m = 1.5;
    options.pedestrians =
        drivers::sim::RandomRoutes(sim.world->collision, config.sim.pedestrians, options.crowd.radius_m, area, rng);
    spdlog::info("simulator: {} pedestrian(s) walking near the start", options.pedestrians.size());
  }
  {
    drivers::sim::DiffDriveSim probe(sim.world->collision, config.sim.robot.base, start);
    if (probe.Collides(start)) {
      throw std::runtime_error("sim.start: the robot at (" + std::to_string(start.x_m) + ", " +
                               std::to_string(start.y_m) + ") overlaps an obstacle or is outside the world");
    }
  }
  sim.robot = std::make_unique<drivers::sim::SimRobot>(sim.world, options);
  return sim;
}

NamedMap InitialMap(const Config& config, const drivers::sim::World* world) {
  if (!config.map.file.empty()) return {config.map.file.stem().string(), nav::LoadMap(config.map.file)};
  if (world != nullptr && world->source_map) return {config.sim.world.stem().string(), *world->source_map};
  if (world != nullptr) return {config.sim.world.stem().string() + "-collision", world->collision};
  throw std::runtime_error("map.file: required when the simulator is disabled");
}

}  // namespace corridor::server
