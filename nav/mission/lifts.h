// Buildings, floors and lifts. A building has floors, each with its own map (and map frame); a lift serves some of
// them, with a stop on each: the lift's door (a line on that floor's map) and its lobby pose, where the robot waits
// outside facing the door. The car is a car_width_m x car_depth_m rectangle behind the door; the robot rides at its
// centre, facing in.
//
// A mission whose goals lie on other floors goes through lifts (ThroughLifts): to the lobby of a lift serving both
// floors, then a ride goal, then on. A ride (LiftRide) goes:
//   calling    the lift is called to the floor; wait until it reports being there with its door open;
//   boarding   the car must be empty: the depth scan shows nothing inside it (clear of its walls) for empty_frames
//              frames in a row; then straight in to the car's centre (turn, then drive, on odometry);
//   riding     the floor is asked for; once the lift reports it there with the door open, the robot's pose on the
//              new floor's map is its pose in the car carried over (car_to * car_from^-1 * pose): the caller
//              switches to that floor's map and sets the pose;
//   leaving    straight out to the lobby there (turning round in the car first), facing away from the door; the
//              lift is released.
// Cancelled with the robot in the car, the ride winds up rather than stopping there (WindUp).
// A refusal or failure from the lift controller, or a timeout (calling, an occupied car, riding), ends the mission
// with the reason, and the lift is released.
//
// Pure logic: the mission runner feeds it the time, the robot's poses, each frame's depth scan and what the lift
// controller reports, and passes on what it asks.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/mission/doors.h"
#include "nav/mission/mission.h"

namespace corridor::nav {

struct LiftStop {
  std::string floor;
  Door door;    // the lift's door on this floor (its id names the lift and the floor)
  Pose2 lobby;  // outside, facing the door
};

struct Lift {
  std::string id;
  double car_width_m = 1.4;
  double car_depth_m = 1.4;
  std::vector<LiftStop> stops;

  const LiftStop* StopAt(const std::string& floor) const;
};

// Where the robot rides on `stop`'s floor: the car's centre, facing into the car (away from the lobby).
Pose2 CarPose(const Lift& lift, const LiftStop& stop);

struct Floor {
  std::string name;
  std::string map;  // the map library's name of its map
};

struct Building {
  std::string name;
  std::vector<Floor> floors;
  std::vector<Lift> lifts;

  bool empty() const { return floors.empty(); }
  const Floor* FloorNamed(const std::string& floor) const;
  const Floor* FloorOfMap(const std::string& map) const;
  const Lift* LiftNamed(const std::string& id) const;
};

// Throws std::invalid_argument naming what is wrong: floors without names or maps or twice, lifts with fewer than two
// stops, stops on unknown floors or twice on one, a lobby too close to its door.
void Validate(const Building& building);
// One stop: on a floor of `building`, a door 0.3 m wide at least, the lobby 0.3 m from it at least. Throws
// std::invalid_argument saying what is wrong.
void ValidateStop(const Building& building, const LiftStop& stop);
// Adds `stop` to lift `lift` (replacing its stop on that floor; a lift of that id is made, with the default car, when
// there is none). Its door is named "LIFT@FLOOR".
void PutStop(Building& building, const std::string& lift, LiftStop stop);

// The goals with lift rides put in where a goal is on another floor than the one before it (the first on
// `start_floor`): a goal to the lobby of the first lift serving both floors, then a ride goal (GoalAction::kRideLift,
// pose: that lobby, floor: the floor ridden to). Goals with an empty floor are on the floor before them. Throws
// std::invalid_argument for an unknown floor or when no lift serves both.
std::vector<MissionGoal> ThroughLifts(const Building& building, const std::string& start_floor,
                                      std::vector<MissionGoal> goals);

struct LiftOptions {
  double call_timeout_s = 120.0;   // from calling the lift until it is there with its door open
  double ride_timeout_s = 120.0;   // from asking for the floor until the door opens there
  double empty_wait_s = 60.0;      // the car stays occupied this long: give up
  int empty_frames = 3;            // frames in a row with the car empty before boarding
  double wall_clearance_m = 0.15;  // points this near the car's walls (or beyond them) are the walls
  int occupied_points = 5;         // this many scan points inside the car: someone (or something) is in it
  double speed_mps = 0.2;          // boarding and leaving
  double turn_rps = 0.6;
  double position_tolerance_m = 0.04;
  double yaw_tolerance_rad = 0.05;
};
// Throws std::invalid_argument naming the bad option.
void Validate(const LiftOptions& options);

// What the lift controller says of a lift.
struct LiftReport {
  std::string floor;       // where the car is (or last was)
  bool door_open = false;  // its door, on that floor
  bool moving = false;
  bool refused = false;  // the controller will not take the robot; detail says why
  bool failed = false;   // no answer or a bad one; detail says what
  std::string detail;
};
using LiftReports = std::map<std::string, LiftReport>;

// A request to the lift controller: come to `floor` and open there, or (release) the robot is done with the lift.
struct LiftRequest {
  std::string lift;
  std::string floor;
  bool release = false;
};

enum class LiftPhase { kCalling, kWaitingForEmpty, kBoarding, kRiding, kLeaving, kDone, kFailed };
const char* ToString(LiftPhase phase);
// Boarding, riding or leaving: the robot is (partly) in the car; localization holds on odometry.
inline bool InCar(LiftPhase phase) {
  return phase == LiftPhase::kBoarding || phase == LiftPhase::kRiding || phase == LiftPhase::kLeaving;
}

struct LiftStep {
  Twist2 twist;
  LiftPhase phase = LiftPhase::kCalling;
  std::vector<LiftRequest> requests;
  // Arrived on the new floor: switch to this floor's map with the robot at this pose (its map frame).
  std::optional<std::pair<std::string, Pose2>> switch_floor;
  double remaining_m = 0.0;  // boarding or leaving: to the target
  std::string error;         // kFailed: why
};

class LiftRide {
 public:
  // Riding `lift` from floor `from` to floor `to`, both served by it; the robot stands at the lobby on `from`.
  // Throws std::invalid_argument when the lift does not serve both floors.
  LiftRide(const LiftOptions& options, Lift lift, const std::string& from, const std::string& to, double now_s);

  // The first requests (the call), to send at once.
  std::vector<LiftRequest> Begin();
  // One frame: `pose` in the current floor's map, `odom` in the odometry frame, `scan` this frame's depth scan
  // (base frame; null: none), `report` the controller's latest for this lift (null: nothing yet).
  LiftStep Update(double now_s, const Pose2& pose, const Pose2& odom, const std::vector<Eigen::Vector2d>* scan,
                  const LiftReport* report);
  // The ride is abandoned (the mission ended): the lift is released, unless that was done.
  std::vector<LiftRequest> Abandon();
  // The mission is cancelled: true when the robot is in the car and the ride must go on until it is out, so that it
  // is never left in a car that others call, nor on one floor with another floor's map. Boarding: it backs out to the
  // lobby it came from. Riding: it goes on to the floor asked for (the caller switches maps on arrival) and out to the
  // lobby there. Leaving: it goes on out. False before boarding: there is nothing to finish (Abandon releases the
  // lift).
  bool WindUp();
  bool winding_up() const { return winding_up_; }
  LiftPhase phase() const { return phase_; }
  const std::string& lift_id() const { return lift_.id; }

 private:
  LiftStep Fail(std::string why);
  // Turn toward `target`, drive to it, turn to its heading; true once there.
  bool DriveTo(const Pose2& odom, const Pose2& target, LiftStep& step) const;
  // Scan points (base frame) inside the car seen from `pose` on the boarding floor, clear of its walls.
  int PointsInCar(const Pose2& pose, const std::vector<Eigen::Vector2d>& scan) const;

  LiftOptions options_;
  Lift lift_;
  const LiftStop* from_;
  const LiftStop* to_;
  LiftPhase phase_ = LiftPhase::kCalling;
  double phase_started_s_;
  int empty_in_a_row_ = 0;
  Pose2 target_;        // boarding or leaving, odometry frame
  Pose2 boarded_pose_;  // the robot's map pose in the car, on the boarding floor
  bool released_ = false;
  bool winding_up_ = false;
};

}  // namespace corridor::nav
