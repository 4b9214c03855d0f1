#include "server/app/simulator.h"

#include <boost/asio/post.hpp>

#include <spdlog/spdlog.h>

#include <random>
#include <sstream>

#include "nav/map/map_io.h"
#include "server/store/saved_pose.h"

namespace corridor::server {

Devices Simulator::devices(const Config& config) const {
  const bool laser = config.devices.laser.driver == DeviceDriver::kSim;
  const bool camera = config.devices.camera.driver == DeviceDriver::kSim;
  Devices out{camera ? robot.get() : nullptr, *robot, laser ? robot.get() : nullptr, robot.get(), robot.get(), floors};
  out.slots.push_back({nav::Device::kBase, "sim", "", nullptr});
  if (laser) out.slots.push_back({nav::Device::kLaser, "sim", "", nullptr});
  if (camera) out.slots.push_back({nav::Device::kCamera, "sim", "", nullptr});
  if (camera && config.devices.camera.pan_driver == DeviceDriver::kSim) out.pan = robot.get();
  return out;
}

std::filesystem::path SimPoseFile(const Config& config) { return config.store.state_dir / "sim_pose.json"; }

std::string SimWorldName(const Config& config) {
  if (config.building.floors.empty()) return config.sim.world.string();
  return "building:" + config.building.name + ":" + SimMapName(config);
}

namespace {

// The building's floors side by side, its lifts standing on them (world frame).
std::shared_ptr<const drivers::sim::Floors> BuildingFloors(const Config& config, drivers::sim::SimOptions& sim) {
  std::vector<nav::OccupancyGrid> maps;
  for (const FloorOptions& f : config.building.floors) {
    try {
      maps.push_back(nav::LoadMap(f.map));
    } catch (const nav::MapFileError& e) {
      throw std::runtime_error("building.floors: floor " + f.name + ": " + e.what());
    }
  }
  auto floors =
      std::make_shared<drivers::sim::Floors>(drivers::sim::FloorsSideBySide(maps, config.building.sim_floor_gap_m));
  const auto offset_of = [&](const std::string& floor) {
    for (std::size_t i = 0; i < config.building.floors.size(); ++i) {
      if (config.building.floors[i].name == floor) return floors->offsets[i];
    }
    return Eigen::Vector2d(Eigen::Vector2d::Zero());
  };
  for (const nav::Lift& lift : config.building.lifts) {
    drivers::sim::SimLiftOptions o;
    o.id = lift.id;
    o.car_width_m = lift.car_width_m;
    o.car_depth_m = lift.car_depth_m;
    o.travel_s = config.building.sim_travel_s;
    for (const nav::LiftStop& stop : lift.stops) {
      const Eigen::Vector2d shift = offset_of(stop.floor);
      nav::Pose2 car = nav::CarPose(lift, stop);
      car.x_m += shift.x();
      car.y_m += shift.y();
      o.stops.push_back({stop.floor, stop.door.a + shift, stop.door.b + shift, car});
    }
    sim.lifts.push_back(std::move(o));
  }
  return floors;
}

}  // namespace

Simulator MakeSimulator(const Config& config) {
  Simulator sim;
  drivers::sim::SimOptions options = config.sim.robot;
  if (!config.building.floors.empty()) sim.floors = BuildingFloors(config, options);
  sim.world = [&] {
    drivers::sim::World w = sim.floors ? drivers::sim::WorldFromMap(sim.floors->map, config.sim.world_options)
                                       : drivers::sim::LoadWorld(config.sim.world, config.sim.world_options);
    drivers::sim::AddObstacles(w, config.sim.obstacles);  // in the world, not in its map
    if (config.sim.robot.dock) drivers::sim::AddDock(w, drivers::sim::SimDock(*config.sim.robot.dock));
    return std::make_shared<const drivers::sim::World>(std::move(w));
  }();
  nav::Pose2 start = config.sim.robot.start;
  if (const std::optional<SavedPose> saved = LoadSavedPose(SimPoseFile(config));
      saved && saved->place == SimWorldName(config)) {
    const drivers::sim::DiffDriveSim probe(sim.world->collision, config.sim.robot.base, saved->pose);
    if (probe.Collides(saved->pose)) {
      spdlog::warn("simulator: the robot's saved pose overlaps something now; starting at sim.start");
    } else {
      start = saved->pose;
      spdlog::info("simulator: the robot is where the last run left it: ({:.2f}, {:.2f})", start.x_m, start.y_m);
    }
  }
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
      std::ostringstream what;
      what.precision(3);
      what << "sim.start: the robot at (" << start.x_m << ", " << start.y_m
           << ") overlaps an obstacle or is outside the world";
      throw std::runtime_error(what.str());
    }
  }
  sim.robot = std::make_unique<drivers::sim::SimRobot>(sim.world, options);
  return sim;
}

NamedMap InitialMap(const Config& config, const drivers::sim::World* world) {
  if (!config.building.floors.empty()) {
    // The floor the robot was on when the daemon stopped (localization's saved pose names its map).
    const FloorOptions* floor = &config.building.floors.front();
    if (const std::optional<SavedPose> saved = LoadSavedPose(config.store.state_dir / "pose.json")) {
      for (const FloorOptions& f : config.building.floors) {
        if (f.map.stem().string() == saved->place) floor = &f;
      }
    }
    try {
      return {floor->map.stem().string(), nav::LoadMap(floor->map)};
    } catch (const nav::MapFileError& e) {
      throw std::runtime_error("building.floors: floor " + floor->name + ": " + e.what());
    }
  }
  if (!config.map.file.empty()) return {config.map.file.stem().string(), nav::LoadMap(config.map.file)};
  if (world != nullptr && world->source_map) return {config.sim.world.stem().string(), *world->source_map};
  if (world != nullptr) return {config.sim.world.stem().string() + "-collision", world->collision};
  throw std::runtime_error("map.file: required when the simulator is disabled");
}

void SimLiftController::Call(const std::string& lift, const std::string& floor, Done done) {
  nav::LiftReport report;
  if (!sim_.CallLift(lift, floor)) {
    report.refused = true;
    report.detail = "the simulator has no lift '" + lift + "' stopping at floor '" + floor + "'";
  }
  boost::asio::post(io_, [done = std::move(done), report = std::move(report)]() mutable { done(std::move(report)); });
}

void SimLiftController::State(const std::string& lift, Done done) {
  nav::LiftReport report;
  report.failed = true;
  report.detail = "the simulator has no lift '" + lift + "'";
  for (const drivers::sim::SimLiftState& l : sim_.lifts()) {
    if (l.id != lift) continue;
    report = nav::LiftReport{};
    report.floor = l.floor;
    report.door_open = l.door_open;
    report.moving = !l.destination.empty();
  }
  boost::asio::post(io_, [done = std::move(done), report = std::move(report)]() mutable { done(std::move(report)); });
}

void SimLiftController::Release(const std::string& lift) { sim_.CallLift(lift, ""); }

std::optional<bool> SimDoorController::IsOpen(const std::string& door) const {
  for (const auto& [id, open] : sim_.doors()) {
    if (id == door) return open;
  }
  return std::nullopt;
}

void SimDoorController::Answer(Done done, nav::DoorReport report) {
  boost::asio::post(io_, [done = std::move(done), report = std::move(report)]() mutable { done(std::move(report)); });
}

void SimDoorController::Open(const std::string& door, Done done) {
  nav::DoorReport report;
  const std::optional<bool> open = IsOpen(door);
  if (!open) {
    report.status = nav::DoorStatus::kRefused;
    report.detail = "the simulator has no door '" + door + "'";
  } else if (*open) {
    report.status = nav::DoorStatus::kOpen;
  } else {
    report.status = nav::DoorStatus::kOpening;
    asked_.try_emplace(door, sim_.now_ns());
  }
  Answer(std::move(done), std::move(report));
}

void SimDoorController::State(const std::string& door, Done done) {
  nav::DoorReport report;
  const std::optional<bool> open = IsOpen(door);
  const auto asked = asked_.find(door);
  if (!open) {
    report.status = nav::DoorStatus::kFailed;
    report.detail = "the simulator has no door '" + door + "'";
  } else if (*open) {
    report.status = nav::DoorStatus::kOpen;
  } else if (asked == asked_.end()) {
    report.status = nav::DoorStatus::kClosed;
  } else {
    report.status = nav::DoorStatus::kOpening;
    if (sim_.now_ns() - asked->second >= drivers::FromSeconds(kDoorOpenS)) sim_.SetDoorOpen(door, true);
  }
  Answer(std::move(done), std::move(report));
}

void SimDoorController::Release(const std::string& door) {
  if (asked_.erase(door) > 0) sim_.SetDoorOpen(door, false);
}

}  // namespace corridor::server
