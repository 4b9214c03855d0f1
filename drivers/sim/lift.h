// A simulated lift: a car with a door on each floor it serves, in a world whose floors stand side by side (one
// scene for the ray caster). Called to a floor, the car closes its door, travels travel_s per floor, and opens the
// door there; a robot standing in the car when it leaves is carried along: its pose relative to the car is kept
// (its odometry does not move). The car's walls are fixed panels in the world; its doors are panels that vanish when
// open. What calls it is the building's lift controller (server/fleet/lifts.h); the simulator only moves it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "drivers/sim/door.h"
#include "nav/geometry/pose2.h"

namespace corridor::drivers::sim {

struct SimLiftStop {
  std::string floor;
  Eigen::Vector2d door_from = Eigen::Vector2d::Zero();  // the car's door on this floor (world frame)
  Eigen::Vector2d door_to = Eigen::Vector2d::Zero();
  nav::Pose2 car;  // the car's centre there, facing in from the door (world frame)
};

struct SimLiftOptions {
  std::string id;
  double car_width_m = 1.4;
  double car_depth_m = 1.4;
  std::vector<SimLiftStop> stops;  // the first is where the car starts, its door closed
  double travel_s = 4.0;           // per floor travelled
};

struct SimLiftState {
  std::string id;
  std::string floor;        // where the car is (the last floor passed while it moves)
  std::string destination;  // where it goes; "" when standing
  bool door_open = false;
};

class SimLift {
 public:
  explicit SimLift(const SimLiftOptions& options);

  const std::string& id() const { return options_.id; }
  // Sends the car to `floor` (its door opens there); false for a floor it does not serve.
  bool Call(const std::string& floor, double now_s);
  // The door closes where the car stands.
  void Release() { door_open_ = false; }
  // Moves the car; when it arrives with the robot (at `robot`, world frame) aboard, returns where the robot is now.
  std::optional<nav::Pose2> Step(double now_s, const nav::Pose2& robot);
  SimLiftState state() const;

  // The car's walls on every floor and its doors there (closed ones solid), for collisions and the camera.
  const std::vector<SimDoor>& walls() const { return walls_; }
  std::vector<const SimDoor*> closed_doors() const;

 private:
  bool Aboard(const SimLiftStop& stop, const nav::Pose2& robot) const;

  SimLiftOptions options_;
  std::vector<SimDoor> walls_;
  std::vector<SimDoor> doors_;  // one per stop
  std::size_t at_ = 0;          // the stop the car is at (or left)
  std::optional<std::size_t> going_to_;
  double arrives_s_ = 0.0;
  bool door_open_ = false;
};

}  // namespace corridor::drivers::sim
