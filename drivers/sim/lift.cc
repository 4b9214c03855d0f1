#include "drivers/sim/lift.h"

#include <algorithm>
#include <cmath>

namespace corridor::drivers::sim {
namespace {

constexpr double kWallThicknessM = 0.1;
constexpr double kWallHeightM = 2.2;

SimDoor Panel(const nav::Pose2& car, Eigen::Vector2d from, Eigen::Vector2d to) {
  SimDoorOptions o;
  o.from = car.Transform(from);
  o.to = car.Transform(to);
  o.thickness_m = kWallThicknessM;
  o.height_m = kWallHeightM;
  return SimDoor(o);
}

}  // namespace

SimLift::SimLift(const SimLiftOptions& options) : options_(options) {
  const double d = options.car_depth_m / 2.0 + kWallThicknessM / 2.0;
  const double w = options.car_width_m / 2.0 + kWallThicknessM / 2.0;
  for (const SimLiftStop& stop : options.stops) {
    // The car's frame: x into the car from its door, y across. Back and sides; the front beside the door.
    walls_.push_back(Panel(stop.car, {d, -w}, {d, w}));
    walls_.push_back(Panel(stop.car, {-d, w}, {d, w}));
    walls_.push_back(Panel(stop.car, {-d, -w}, {d, -w}));
    const nav::Pose2 inverse = stop.car.Inverse();
    const double y1 = inverse.Transform(stop.door_from).y();
    const double y2 = inverse.Transform(stop.door_to).y();
    if (std::min(y1, y2) > -w + 0.02) walls_.push_back(Panel(stop.car, {-d, -w}, {-d, std::min(y1, y2)}));
    if (std::max(y1, y2) < w - 0.02) walls_.push_back(Panel(stop.car, {-d, std::max(y1, y2)}, {-d, w}));
    SimDoorOptions door;
    door.id = options.id + "@" + stop.floor;
    door.from = stop.door_from;
    door.to = stop.door_to;
    doors_.emplace_back(door);
  }
}

bool SimLift::Call(const std::string& floor, double now_s) {
  const auto it = std::find_if(options_.stops.begin(), options_.stops.end(),
                               [&](const SimLiftStop& s) { return s.floor == floor; });
  if (it == options_.stops.end()) return false;
  const std::size_t to = static_cast<std::size_t>(it - options_.stops.begin());
  if (!going_to_ && to == at_) {
    door_open_ = true;
    return true;
  }
  if (going_to_ == to) return true;  // on its way there already: asked again, it keeps going
  door_open_ = false;
  going_to_ = to;
  const double floors = std::abs(static_cast<double>(to) - static_cast<double>(at_));
  arrives_s_ = now_s + options_.travel_s * std::max(1.0, floors);
  return true;
}

bool SimLift::Aboard(const SimLiftStop& stop, const nav::Pose2& robot) const {
  const Eigen::Vector2d local = stop.car.Inverse().Transform(robot.translation());
  return std::abs(local.x()) < options_.car_depth_m / 2.0 && std::abs(local.y()) < options_.car_width_m / 2.0;
}

std::optional<nav::Pose2> SimLift::Step(double now_s, const nav::Pose2& robot) {
  if (!going_to_ || now_s < arrives_s_) return std::nullopt;
  const SimLiftStop& from = options_.stops[at_];
  const SimLiftStop& to = options_.stops[*going_to_];
  at_ = *going_to_;
  going_to_.reset();
  door_open_ = true;
  if (!Aboard(from, robot)) return std::nullopt;
  return to.car * from.car.Inverse() * robot;
}

SimLiftState SimLift::state() const {
  SimLiftState s;
  s.id = options_.id;
  s.floor = options_.stops[at_].floor;
  if (going_to_) s.destination = options_.stops[*going_to_].floor;
  s.door_open = door_open_ && !going_to_;
  return s;
}

std::vector<const SimDoor*> SimLift::closed_doors() const {
  std::vector<const SimDoor*> out;
  for (std::size_t i = 0; i < doors_.size(); ++i) {
    if (!(door_open_ && !going_to_ && i == at_)) out.push_back(&doors_[i]);
  }
  return out;
}

}  // namespace corridor::drivers::sim
