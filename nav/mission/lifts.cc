#include "nav/mission/lifts.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace corridor::nav {
namespace {

// The unit normal of the door's line pointing away from the lobby: into the car.
Eigen::Vector2d IntoCar(const LiftStop& stop) {
  const Eigen::Vector2d along = (stop.door.b - stop.door.a).normalized();
  Eigen::Vector2d normal(-along.y(), along.x());
  const Eigen::Vector2d middle = (stop.door.a + stop.door.b) / 2.0;
  if (normal.dot(middle - stop.lobby.translation()) < 0.0) normal = -normal;
  return normal;
}

}  // namespace

const LiftStop* Lift::StopAt(const std::string& floor) const {
  for (const LiftStop& s : stops) {
    if (s.floor == floor) return &s;
  }
  return nullptr;
}

Pose2 CarPose(const Lift& lift, const LiftStop& stop) {
  const Eigen::Vector2d in = IntoCar(stop);
  const Eigen::Vector2d centre = (stop.door.a + stop.door.b) / 2.0 + in * (lift.car_depth_m / 2.0);
  return {centre.x(), centre.y(), std::atan2(in.y(), in.x())};
}

const Floor* Building::FloorNamed(const std::string& floor) const {
  for (const Floor& f : floors) {
    if (f.name == floor) return &f;
  }
  return nullptr;
}

const Floor* Building::FloorOfMap(const std::string& map) const {
  for (const Floor& f : floors) {
    if (f.map == map) return &f;
  }
  return nullptr;
}

const Lift* Building::LiftNamed(const std::string& id) const {
  for (const Lift& l : lifts) {
    if (l.id == id) return &l;
  }
  return nullptr;
}

void Validate(const Building& b) {
  std::set<std::string> names;
  std::set<std::string> maps;
  for (const Floor& f : b.floors) {
    if (f.name.empty() || f.map.empty()) throw std::invalid_argument("building.floors: each needs a name and a map");
    if (!names.insert(f.name).second) throw std::invalid_argument("building.floors: floor '" + f.name + "' twice");
    if (!maps.insert(f.map).second) throw std::invalid_argument("building.floors: map '" + f.map + "' on two floors");
  }
  std::set<std::string> lifts;
  for (const Lift& l : b.lifts) {
    const std::string where = "building.lifts: lift '" + l.id + "'";
    if (l.id.empty() || !lifts.insert(l.id).second) throw std::invalid_argument(where + ": needs an id of its own");
    if (l.stops.size() < 2) throw std::invalid_argument(where + ": needs stops on two floors at least");
    if (!(l.car_width_m > 0.0 && l.car_depth_m > 0.0)) throw std::invalid_argument(where + ": car size must be > 0");
    std::set<std::string> served;
    for (const LiftStop& s : l.stops) {
      try {
        ValidateStop(b, s);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + ": " + e.what());
      }
      if (!served.insert(s.floor).second) throw std::invalid_argument(where + ": two stops on '" + s.floor + "'");
    }
  }
}

void ValidateStop(const Building& b, const LiftStop& s) {
  if (b.FloorNamed(s.floor) == nullptr) throw std::invalid_argument("no floor '" + s.floor + "'");
  const Eigen::Vector2d middle = (s.door.a + s.door.b) / 2.0;
  if ((s.door.b - s.door.a).norm() < 0.3 || (middle - s.lobby.translation()).norm() < 0.3) {
    throw std::invalid_argument("on '" + s.floor +
                                "' the door must be 0.3 m wide at least and the lobby 0.3 m from it");
  }
}

void PutStop(Building& building, const std::string& lift, LiftStop stop) {
  stop.door.id = lift + "@" + stop.floor;
  auto it = std::find_if(building.lifts.begin(), building.lifts.end(), [&](const Lift& l) { return l.id == lift; });
  if (it == building.lifts.end()) {
    building.lifts.push_back(Lift{.id = lift, .stops = {}});
    it = std::prev(building.lifts.end());
  }
  std::erase_if(it->stops, [&](const LiftStop& s) { return s.floor == stop.floor; });
  it->stops.push_back(std::move(stop));
}

std::vector<MissionGoal> ThroughLifts(const Building& building, const std::string& start_floor,
                                      std::vector<MissionGoal> goals) {
  std::vector<MissionGoal> out;
  std::string floor = start_floor;
  for (MissionGoal& goal : goals) {
    if (goal.floor.empty()) goal.floor = floor;
    if (building.FloorNamed(goal.floor) == nullptr) throw std::invalid_argument("no floor '" + goal.floor + "'");
    if (goal.floor != floor) {
      const auto serves = [&](const Lift& l) { return l.StopAt(floor) != nullptr && l.StopAt(goal.floor) != nullptr; };
      const auto lift = std::find_if(building.lifts.begin(), building.lifts.end(), serves);
      if (lift == building.lifts.end()) {
        throw std::invalid_argument("no lift goes from floor '" + floor + "' to floor '" + goal.floor + "'");
      }
      MissionGoal ride;
      ride.pose = lift->StopAt(floor)->lobby;
      ride.has_yaw = true;
      ride.action = GoalAction::kRideLift;
      ride.floor = floor;
      ride.lift = lift->id;
      ride.ride_to = goal.floor;
      ride.max_speed_mps = goal.max_speed_mps;
      out.push_back(ride);
    }
    floor = goal.floor;
    out.push_back(std::move(goal));
  }
  return out;
}

void Validate(const LiftOptions& o) {
  if (!(o.call_timeout_s > 0.0 && o.ride_timeout_s > 0.0 && o.empty_wait_s > 0.0 && o.empty_frames >= 1 &&
        o.wall_clearance_m >= 0.0 && o.occupied_points >= 1 && o.speed_mps > 0.0 && o.turn_rps > 0.0 &&
        o.position_tolerance_m > 0.0 && o.yaw_tolerance_rad > 0.0)) {
    throw std::invalid_argument("lifts: timeouts, speeds, tolerances and counts must be > 0 (clearance >= 0)");
  }
}

const char* ToString(LiftPhase phase) {
  switch (phase) {
    case LiftPhase::kCalling: return "calling";
    case LiftPhase::kWaitingForEmpty: return "waiting_for_empty_car";
    case LiftPhase::kBoarding: return "boarding";
    case LiftPhase::kRiding: return "riding";
    case LiftPhase::kLeaving: return "leaving";
    case LiftPhase::kDone: return "done";
    case LiftPhase::kFailed: return "failed";
  }
  return "unknown";
}

LiftRide::LiftRide(const LiftOptions& options, Lift lift, const std::string& from, const std::string& to, double now_s)
    : options_(options), lift_(std::move(lift)), phase_started_s_(now_s) {
  Validate(options_);
  from_ = lift_.StopAt(from);
  to_ = lift_.StopAt(to);
  if (from_ == nullptr || to_ == nullptr || from == to) {
    throw std::invalid_argument("lift '" + lift_.id + "' does not go from '" + from + "' to '" + to + "'");
  }
}

std::vector<LiftRequest> LiftRide::Begin() { return {{lift_.id, from_->floor, false}}; }

bool LiftRide::WindUp() {
  winding_up_ = InCar(phase_);
  return winding_up_;
}

std::vector<LiftRequest> LiftRide::Abandon() {
  if (released_) return {};
  released_ = true;
  return {{lift_.id, "", true}};
}

LiftStep LiftRide::Fail(std::string why) {
  phase_ = LiftPhase::kFailed;
  LiftStep step;
  step.phase = phase_;
  step.error = std::move(why);
  step.requests = Abandon();
  return step;
}

int LiftRide::PointsInCar(const Pose2& pose, const std::vector<Eigen::Vector2d>& scan) const {
  // The car in the frame of its centre: x into the car, y across.
  const Pose2 car = CarPose(lift_, *from_);
  const Pose2 car_T_base = car.Inverse() * pose;
  const double half_depth = lift_.car_depth_m / 2.0 - options_.wall_clearance_m;
  const double half_width = lift_.car_width_m / 2.0 - options_.wall_clearance_m;
  int inside = 0;
  for (const Eigen::Vector2d& p : scan) {
    const Eigen::Vector2d q = car_T_base.Transform(p);
    if (std::abs(q.x()) < half_depth && std::abs(q.y()) < half_width) ++inside;
  }
  return inside;
}

bool LiftRide::DriveTo(const Pose2& odom, const Pose2& target, LiftStep& step) const {
  const Eigen::Vector2d to = target.translation() - odom.translation();
  step.remaining_m = to.norm();
  const auto turn = [&](double error) { return std::clamp(2.0 * error, -options_.turn_rps, options_.turn_rps); };
  if (step.remaining_m > options_.position_tolerance_m) {
    const double bearing = WrapAngle(std::atan2(to.y(), to.x()) - odom.yaw_rad);
    // Facing the target well enough: drive, steering the rest; else turn on the spot first.
    if (std::abs(bearing) > 0.2) {
      step.twist.angular_rps = turn(bearing);
    } else {
      step.twist.linear_mps = std::min(options_.speed_mps, 0.8 * step.remaining_m + 0.02);
      step.twist.angular_rps = turn(bearing);
    }
    return false;
  }
  const double yaw_error = WrapAngle(target.yaw_rad - odom.yaw_rad);
  if (std::abs(yaw_error) <= options_.yaw_tolerance_rad) return true;
  step.twist.angular_rps = turn(yaw_error);
  return false;
}

LiftStep LiftRide::Update(double now_s, const Pose2& pose, const Pose2& odom, const std::vector<Eigen::Vector2d>* scan,
                          const LiftReport* report) {
  LiftStep step;
  step.phase = phase_;
  if (phase_ == LiftPhase::kDone || phase_ == LiftPhase::kFailed) return step;
  if (report != nullptr && report->refused) return Fail("lift " + lift_.id + " refused: " + report->detail);
  const double waited_s = now_s - phase_started_s_;
  const auto enter = [&](LiftPhase phase) {
    phase_ = phase;
    phase_started_s_ = now_s;
  };
  // The car is at `floor` with its door open.
  const auto open_at = [&](const LiftStop& stop) {
    return report != nullptr && !report->failed && report->floor == stop.floor && report->door_open;
  };
  switch (phase_) {
    case LiftPhase::kCalling:
      if (open_at(*from_)) {
        enter(LiftPhase::kWaitingForEmpty);
        empty_in_a_row_ = 0;
      } else if (waited_s > options_.call_timeout_s) {
        return Fail("lift " + lift_.id + " did not come to floor " + from_->floor + " with its door open within " +
                    std::to_string(static_cast<int>(options_.call_timeout_s)) + " s");
      }
      break;
    case LiftPhase::kWaitingForEmpty:
      if (!open_at(*from_)) {  // it closed (or left) again: call it back
        enter(LiftPhase::kCalling);
        step.requests.push_back({lift_.id, from_->floor, false});
        break;
      }
      if (scan != nullptr) {
        empty_in_a_row_ = PointsInCar(pose, *scan) < options_.occupied_points ? empty_in_a_row_ + 1 : 0;
      }
      if (empty_in_a_row_ >= options_.empty_frames) {
        enter(LiftPhase::kBoarding);
        // The car's centre, where the map puts it, in the odometry frame (which the robot drives in).
        target_ = odom * pose.Inverse() * CarPose(lift_, *from_);
      } else if (waited_s > options_.empty_wait_s) {
        return Fail("the car of lift " + lift_.id + " stayed occupied for " +
                    std::to_string(static_cast<int>(options_.empty_wait_s)) + " s");
      }
      break;
    case LiftPhase::kBoarding:
      if (winding_up_) {
        // Cancelled on the way in: back out to the lobby it came from, on this floor.
        to_ = from_;
        const Pose2 lobby_out{from_->lobby.x_m, from_->lobby.y_m, WrapAngle(from_->lobby.yaw_rad + M_PI)};
        target_ = odom * pose.Inverse() * lobby_out;
        enter(LiftPhase::kLeaving);
        break;
      }
      if (!open_at(*from_)) {
        // The door closing on the robot: stand still; the lift must open it again.
        step.phase = phase_;
        return step;
      }
      if (DriveTo(odom, target_, step)) {
        enter(LiftPhase::kRiding);
        boarded_pose_ = pose;
        step.twist = Twist2{};
        step.requests.push_back({lift_.id, to_->floor, false});
      }
      break;
    case LiftPhase::kRiding:
      if (open_at(*to_)) {
        const Pose2 arrived = CarPose(lift_, *to_) * CarPose(lift_, *from_).Inverse() * boarded_pose_;
        step.switch_floor = std::make_pair(to_->floor, arrived);
        // Out to the lobby there, facing away from the door.
        const Pose2 lobby_out{to_->lobby.x_m, to_->lobby.y_m, WrapAngle(to_->lobby.yaw_rad + M_PI)};
        target_ = odom * arrived.Inverse() * lobby_out;
        enter(LiftPhase::kLeaving);
      } else if (waited_s > options_.ride_timeout_s) {
        return Fail("lift " + lift_.id + " did not reach floor " + to_->floor + " with its door open within " +
                    std::to_string(static_cast<int>(options_.ride_timeout_s)) + " s");
      }
      break;
    case LiftPhase::kLeaving:
      if (!open_at(*to_)) {
        step.phase = phase_;
        return step;
      }
      if (DriveTo(odom, target_, step)) {
        enter(LiftPhase::kDone);
        step.twist = Twist2{};
        step.requests = Abandon();
      }
      break;
    case LiftPhase::kDone:
    case LiftPhase::kFailed: break;
  }
  step.phase = phase_;
  return step;
}

}  // namespace corridor::nav
