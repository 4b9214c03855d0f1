#include "nav/mission/mission_runner.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "nav/policy/reactive_navigator.h"

namespace corridor::nav {
namespace {

std::unique_ptr<LocalPolicy> MakePolicy(const MissionRunnerOptions& o) {
  if (o.policy == LocalPolicyKind::kVoxelReactive) {
    return std::make_unique<ReactiveNavigator>(o.navigator.follower, o.reactive, o.navigator.replan_distance_m);
  }
  LocalNavigatorOptions navigator = o.navigator;
  if (o.policy == LocalPolicyKind::kMorpIl && !navigator.learned) {
    throw std::invalid_argument("mission.policy morp-il: no network loaded (mission.morp_il.weights)");
  }
  if (o.policy == LocalPolicyKind::kTakiguchi && !navigator.direction && !navigator.teach) {
    throw std::invalid_argument("mission.policy takiguchi: no network loaded (mission.takiguchi.weights)");
  }
  if (o.policy != LocalPolicyKind::kMorpIl) navigator.learned = nullptr;  // the rules drive (and teach, if asked)
  navigator.direction_policy = o.policy == LocalPolicyKind::kTakiguchi;
  navigator.fuzzy_policy = o.policy == LocalPolicyKind::kFlmc;
  if (!navigator.direction_policy) navigator.direction = nullptr;
  return std::make_unique<LocalNavigator>(navigator);
}

PolicyMode ModeOf(MorpRbMode mode) {
  switch (mode) {
    case MorpRbMode::kFollow: return PolicyMode::kFollow;
    case MorpRbMode::kChangeLaneLeft: return PolicyMode::kChangeLaneLeft;
    case MorpRbMode::kChangeLaneRight: return PolicyMode::kChangeLaneRight;
    case MorpRbMode::kStopAndTurn: return PolicyMode::kStopAndTurn;
    case MorpRbMode::kOvertake: return PolicyMode::kOvertake;
  }
  return PolicyMode::kNone;
}

std::vector<Eigen::Vector2d> Positions(const std::vector<Waypoint>& path) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(path.size());
  for (const Waypoint& w : path) out.push_back(w.pose.translation());
  return out;
}

}  // namespace

const char* ToString(PolicyMode mode) {
  switch (mode) {
    case PolicyMode::kNone: return "";
    case PolicyMode::kFollow: return "follow";
    case PolicyMode::kChangeLaneLeft: return "change_lane_left";
    case PolicyMode::kChangeLaneRight: return "change_lane_right";
    case PolicyMode::kStopAndTurn: return "stop_and_turn";
    case PolicyMode::kOvertake: return "overtake";
    case PolicyMode::kEvade: return "evade";
    case PolicyMode::kReactive: return "reactive";
    case PolicyMode::kLearned: return "learned";
    case PolicyMode::kWaitingForDepth: return "waiting_for_depth";
    case PolicyMode::kWaitingForDoor: return "waiting_for_door";
  }
  return "unknown";
}

MissionRunner::MissionRunner(const MissionRunnerOptions& options)
    : options_(options), policy_(MakePolicy(options)), door_keeper_(options.doors) {
  Validate(options.docking);
  Validate(options.doors);
  Validate(options.lifts);
}

void MissionRunner::PathSet(const std::vector<Waypoint>& waypoints, MissionUpdate& update) {
  std::vector<Eigen::Vector2d> line;
  for (const Waypoint& w : waypoints) line.push_back(w.pose.translation());
  door_keeper_.SetPath(DoorsOnPath(line, doors_), update.doors);
}

MissionUpdate& MissionRunner::Settle(MissionUpdate& update) {
  if (update.over) ReleaseAll(update);
  return update;
}

void MissionRunner::ReleaseAll(MissionUpdate& update) {
  door_keeper_.ReleaseAll(update.doors);
  waiting_for_door_.clear();
  if (ride_ && !ride_->winding_up()) {
    if (InCar(ride_->phase())) update.hold_localization = false;
    const std::vector<LiftRequest> release = ride_->Abandon();
    update.lifts.insert(update.lifts.end(), release.begin(), release.end());
    ride_.reset();
  }
}

const std::string& MissionRunner::id() const {
  static const std::string kNone;
  return mission_ ? mission_->id() : kNone;
}

MissionSnapshot MissionRunner::Snapshot() const {
  const Mission& m = *mission_;
  MissionSnapshot s;
  s.id = m.id();
  s.status = m.status();
  s.goals = m.goals();
  s.current = m.current();
  s.progress = m.Progress(remaining_m_, leg_length_m_);
  const double speed = std::min(options_.navigator.follower.max_linear_mps, m.speed_limit_mps());
  s.eta_s = m.EtaSeconds(remaining_m_, speed);
  s.remaining_on_leg_m = remaining_m_;
  for (const Waypoint& w : policy_->path()) s.path.push_back(w.pose);
  s.policy = mode_;
  s.error = m.error();
  s.speed_limit_mps = m.speed_limit_mps();
  if (docking_) s.docking = ToString(docking_phase_);
  s.waiting_for_door = waiting_for_door_;
  if (ride_) s.lift = ToString(ride_->phase());
  s.waiting = Waiting();
  return s;
}

std::string MissionRunner::Waiting() const {
  if (!mission_ || (mission_->finished() && !leaving_lift())) return "";
  if (leaving_lift()) return "the robot to leave lift " + ride_->lift_id() + "'s car";
  if (mission_->status() == MissionStatus::kPaused) {
    return paused_unlocalized_ ? "localization: the robot is lost and searches the map for itself" : "";
  }
  if (ride_) {
    switch (ride_->phase()) {
      case LiftPhase::kCalling: return "lift " + ride_->lift_id() + " to come with its door open";
      case LiftPhase::kWaitingForEmpty: return "the car of lift " + ride_->lift_id() + " to be empty";
      case LiftPhase::kRiding: return "lift " + ride_->lift_id() + " to arrive";
      default: return "";
    }
  }
  if (AtDockingGoal()) return "";
  if (!waiting_for_door_.empty()) return "door " + waiting_for_door_ + " to open";
  if (mode_ == PolicyMode::kWaitingForDepth) return "depth frames from the camera";
  if (!policy_->has_path() && planning_) return "a plan";
  if (headway_s_ >= 0.0 && now_s_ - headway_s_ >= options_.waiting_after_s) {
    const int waited = static_cast<int>(now_s_ - headway_s_);
    return "a way past what blocks it (no headway for " + std::to_string(waited) + " s" +
           (options_.give_up_s > 0.0
                ? ", giving up after " + std::to_string(static_cast<int>(options_.give_up_s)) + " s)"
                : ")");
  }
  return "";
}

void MissionRunner::DropPath() {
  policy_->Clear();
  ++generation_;
  planning_ = false;
}

MissionUpdate MissionRunner::Start(Mission mission, std::optional<MissionSnapshot>* cancelled) {
  if (mission_ && mission_->Cancel() && cancelled != nullptr) *cancelled = Snapshot();
  MissionUpdate update;
  ReleaseAll(update);
  mission_.emplace(std::move(mission));
  docking_.reset();
  paused_unlocalized_ = false;
  ResetHeadway();
  DropPath();
  checking_ = false;
  leg_length_m_ = remaining_m_ = 0.0;
  mode_ = PolicyMode::kNone;
  update.persist = true;
  return update;
}

TransitionOutcome MissionRunner::Transition(const std::string& id, bool (Mission::*transition)(), bool drop_path,
                                            MissionUpdate* update) {
  if (!mission_ || mission_->id() != id) return TransitionOutcome::kNotFound;
  if (!((*mission_).*transition)()) return TransitionOutcome::kConflict;
  ResetHeadway();  // a pause, resume or cancel: the time without headway starts again
  if (drop_path) DropPath();
  if (mission_->finished()) docking_.reset();
  update->persist = true;
  update->over = mission_->finished();
  Settle(*update);
  return TransitionOutcome::kOk;
}

TransitionOutcome MissionRunner::Extend(const std::string& id, std::vector<MissionGoal> goals, MissionUpdate* update) {
  if (!mission_ || mission_->id() != id) return TransitionOutcome::kNotFound;
  if (goals.empty() || !mission_->Extend(std::move(goals))) return TransitionOutcome::kConflict;
  update->persist = true;
  return TransitionOutcome::kOk;
}

TransitionOutcome MissionRunner::Pause(const std::string& id, MissionUpdate* update) {
  return Transition(id, &Mission::Pause, false, update);
}
TransitionOutcome MissionRunner::Resume(const std::string& id, MissionUpdate* update) {
  return Transition(id, &Mission::Resume, true, update);
}
TransitionOutcome MissionRunner::Cancel(const std::string& id, MissionUpdate* update) {
  // In a lift's car, the ride winds up (LiftRide::WindUp) after the mission has ended: out of the car first.
  const bool ours = mission_ && mission_->id() == id && !mission_->finished();
  if (ours && ride_ && ride_->WindUp()) update->publish = true;
  return Transition(id, &Mission::Cancel, true, update);
}

MissionUpdate MissionRunner::SetLocalized(bool localized) {
  MissionUpdate update;
  if (!mission_) return update;
  if (!localized && mission_->status() == MissionStatus::kActive) {
    paused_unlocalized_ = Pause(mission_->id(), &update) == TransitionOutcome::kOk;
  } else if (localized && paused_unlocalized_) {
    paused_unlocalized_ = false;
    if (mission_->status() == MissionStatus::kPaused) Resume(mission_->id(), &update);
  }
  return update;
}

LegPlanQuery MissionRunner::LegQuery(const Pose2& from, bool reroute, bool blocked) const {
  const MissionGoal& goal = mission_->current_goal();
  LegPlanQuery q;
  q.ticket = generation_;
  q.reroute = reroute;
  q.blocked = blocked;
  q.start = from.translation();
  q.goal = goal.pose.translation();
  if (goal.has_yaw) q.goal_yaw = goal.pose.yaw_rad;
  // Round what blocked the robot lately, if anything did.
  q.blocking = policy_->Blocking();
  q.blocking_radius_m = options_.navigator.blocked_radius_m;
  q.blocking_cost = static_cast<float>(options_.navigator.blocked_cost);
  return q;
}

MissionUpdate MissionRunner::Tick(double now_s, const std::optional<Pose2>& pose, std::uint64_t planner_version,
                                  bool has_traffic) {
  MissionUpdate update;
  now_s_ = now_s;
  if (leaving_lift()) {
    // The ride drives on the frames; without them the robot holds still.
    if (last_frame_s_ < 0.0 || now_s - last_frame_s_ > options_.no_frames_s) update.command = Twist2{};
    return update;
  }
  if (!mission_ || mission_->finished()) return update;
  const Twist2 still;
  if (!pose || mission_->status() == MissionStatus::kPaused) {
    update.command = still;
    return update;
  }
  if (OffPath()) {
    // Docking and lifts drive on the frames; without them the robot holds still.
    if (last_frame_s_ < 0.0 || now_s - last_frame_s_ > options_.no_frames_s) update.command = still;
    return update;
  }
  if (!policy_->has_path()) {
    if (!planning_) {
      planning_ = true;
      update.plan = LegQuery(*pose, false, false);
    }
    update.command = still;
    return update;
  }
  if (path_version_ != planner_version && !checking_) {
    checking_ = true;
    update.check = PathCheckQuery{generation_, policy_->path(), pose->translation()};
  }
  const double reroute_s = options_.navigator.reroute_s;
  if (reroute_s > 0.0 && !rerouting_ && mission_->status() == MissionStatus::kActive && has_traffic &&
      now_s - routed_s_ > reroute_s) {
    rerouting_ = true;
    routed_s_ = now_s;
    update.plan = LegQuery(*pose, true, false);
  }
  // Driving waits for depth frames; without them there is nothing safe to do but stand still.
  if (last_frame_s_ < 0.0 || now_s - last_frame_s_ > options_.no_frames_s) {
    if (mode_ != PolicyMode::kWaitingForDepth) {
      mode_ = PolicyMode::kWaitingForDepth;
      update.publish = true;
    }
    update.command = still;
  }
  return update;
}

MissionUpdate MissionRunner::Frame(const FrameInput& frame) {
  MissionUpdate update = FrameStep(frame);
  return Settle(update);
}

MissionUpdate MissionRunner::FrameStep(const FrameInput& frame) {
  MissionUpdate update;
  const double dt_s = last_frame_s_ < 0.0 ? 0.0 : frame.now_s - last_frame_s_;
  last_frame_s_ = frame.now_s;
  now_s_ = frame.now_s;
  if (leaving_lift()) return LiftFrame(frame);
  if (!mission_ || mission_->finished() || mission_->status() == MissionStatus::kPaused) return update;
  if (AtDockingGoal()) return DockingFrame(frame);
  if (ride_) return LiftFrame(frame);
  if (!policy_->has_path() || !frame.pose) return update;
  const Pose2& pose = *frame.pose;
  // The tracker's objects, while fresh: people to step out of the way of.
  const bool fresh = frame.tracked != nullptr && frame.now_s - frame.tracked_received_s < options_.stale_tracking_s;
  // A bump since the last frame: remembered where it was, the way the control node says the base was driving.
  if (frame.bump_s && *frame.bump_s > bump_seen_s_ && frame.now_s - *frame.bump_s < options_.fresh_bump_s) {
    bump_seen_s_ = *frame.bump_s;
    policy_->Touched(pose, frame.bump_backing);
  }
  // Doors on the way: asked for ahead, and none driven into before it is open.
  static const DoorReports kNoReports;
  const DoorKeeper::Step door =
      door_keeper_.Update(frame.now_s, remaining_m_, frame.doors ? *frame.doors : kNoReports, update.doors);
  if (door.failure) {
    policy_->Clear();
    mission_->Fail(*door.failure);
    update.persist = update.over = true;
    return update;
  }
  if (door.hold) {
    ResetHeadway();
    update.persist = waiting_for_door_ != door.waiting_for;
    waiting_for_door_ = door.waiting_for;
    mode_ = PolicyMode::kWaitingForDoor;
    update.command = Twist2{};
    update.publish = true;
    return update;
  }
  if (!waiting_for_door_.empty()) {
    waiting_for_door_.clear();
    update.persist = true;
  }
  const double speed_limit = std::min(mission_->speed_limit_mps(), mission_->current_goal().max_speed_mps);
  const LocalStep step = policy_->Update(pose, frame.view, speed_limit, dt_s, fresh ? frame.tracked : nullptr);
  update.step = step;
  remaining_m_ = step.remaining_m;
  mode_ = options_.policy == LocalPolicyKind::kVoxelReactive ? PolicyMode::kReactive
          : step.evading                                     ? PolicyMode::kEvade
          : step.learned                                     ? PolicyMode::kLearned
                                                             : ModeOf(step.mode);
  if (step.done) {
    policy_->Clear();
    ResetHeadway();
    const MissionGoal& goal = mission_->current_goal();
    if (goal.action == GoalAction::kDock && frame.odom) {
      // At the staging pose: onto the dock, from where the map puts it (in the odometry frame, which docking drives
      // in).
      ++generation_;
      docking_.emplace(Docking::Dock(options_.docking, *frame.odom * pose.Inverse() * goal.dock, frame.now_s));
      docking_phase_ = DockingPhase::kSeeking;
      update.persist = true;
      update.command = Twist2{};
      return update;
    }
    if (goal.action == GoalAction::kDock) {
      mission_->Fail("no odometry to dock with");
      update.persist = update.over = true;
      return update;
    }
    if (goal.action == GoalAction::kRideLift) {
      // At the lift's lobby: call it.
      const Lift* lift = building_.LiftNamed(goal.lift);
      try {
        if (lift == nullptr) throw std::invalid_argument("no lift '" + goal.lift + "' in the building");
        ride_.emplace(options_.lifts, *lift, goal.floor, goal.ride_to, frame.now_s);
      } catch (const std::invalid_argument& e) {
        mission_->Fail(e.what());
        update.persist = update.over = true;
        return update;
      }
      ++generation_;
      update.lifts = ride_->Begin();
      update.persist = true;
      update.command = Twist2{};
      return update;
    }
    NextGoal(update);
    return update;
  }
  if (step.replan) {
    DropPath();
    update.command = step.twist;  // still, unless stepping out of someone's way
    return update;
  }
  if (step.blocked) {
    if (!blocked_at_ || (pose.translation() - *blocked_at_).norm() > options_.blocked_area_m) {
      blocked_at_ = pose.translation();
      blocked_count_ = 0;
    }
    if (options_.give_up_blocked > 0 && ++blocked_count_ >= options_.give_up_blocked) {
      GiveUp(pose, "blocked " + std::to_string(blocked_count_) + " times in a row", update);
      return update;
    }
  }
  if (step.blocked && !rerouting_) {
    rerouting_ = true;
    routed_s_ = frame.now_s;
    update.plan = LegQuery(pose, true, true);
  }
  // Headway: a mission that gets no nearer its waypoint for give_up_s, whatever it tried, ends with the reason.
  // Headway is either measure falling: the path left (a detour is longer) or the straight line to the waypoint (a
  // detour may first lead away). Both keep their best across replanning, so trying one way after another in front of
  // the same obstacle is no headway.
  const double direct_m = (mission_->current_goal().pose.translation() - pose.translation()).norm();
  if (headway_s_ < 0.0 || remaining_m_ < best_remaining_m_ - options_.headway_m ||
      direct_m < best_direct_m_ - options_.headway_m) {
    best_remaining_m_ = std::min(best_remaining_m_, remaining_m_);
    best_direct_m_ = std::min(best_direct_m_, direct_m);
    headway_s_ = frame.now_s;
  } else if (options_.give_up_s > 0.0 && frame.now_s - headway_s_ > options_.give_up_s) {
    GiveUp(pose, "no headway for " + std::to_string(static_cast<int>(options_.give_up_s)) + " s", update);
    return update;
  }
  update.command = step.twist;
  update.answers_frame = true;
  update.publish = true;
  return update;
}

void MissionRunner::GiveUp(const Pose2& pose, const std::string& why, MissionUpdate& update) {
  std::ostringstream error;
  error << std::fixed << std::setprecision(2) << "no way forward: " << why << " toward waypoint "
        << mission_->current() + 1 << " near (" << pose.x_m << ", " << pose.y_m << "), " << std::setprecision(1)
        << remaining_m_ << " m from it; what the camera sees blocks every way the planner knows";
  policy_->Clear();
  mission_->Fail(error.str());
  update.command = Twist2{};
  update.persist = update.over = true;
}

void MissionRunner::NextGoal(MissionUpdate& update) {
  ResetHeadway();
  mission_->GoalReached();
  ++generation_;
  remaining_m_ = leg_length_m_ = 0.0;
  update.persist = true;
  update.over = mission_->finished();
  if (!update.over) update.command = Twist2{};  // a brief stop before the next leg
}

void MissionRunner::SetOnCharger(bool on_charger) {
  if (!docking_) docked_ = on_charger;
}

MissionUpdate MissionRunner::DockingFrame(const FrameInput& frame) {
  MissionUpdate update;
  if (!frame.odom) {
    update.command = Twist2{};
    return update;
  }
  if (!docking_) {  // an undocking goal, begun here
    docking_.emplace(Docking::Undock(options_.docking, *frame.odom, frame.now_s));
    docking_phase_ = DockingPhase::kUndocking;
  }
  const DockingStep step = docking_->Update(frame.now_s, *frame.odom, frame.view.scan);
  remaining_m_ = step.remaining_m;
  update.persist = step.phase != docking_phase_;
  docking_phase_ = step.phase;
  if (step.phase == DockingPhase::kFailed) {
    docking_.reset();
    mission_->Fail(step.error);
    update.persist = update.over = true;
    return update;
  }
  if (step.finished()) {
    docked_ = step.phase == DockingPhase::kDocked;
    docking_.reset();
    NextGoal(update);
    return update;
  }
  update.command = step.twist;
  update.docking = true;
  update.answers_frame = true;
  update.publish = true;
  return update;
}

MissionUpdate MissionRunner::LiftFrame(const FrameInput& frame) {
  MissionUpdate update;
  if (!frame.odom || !frame.pose) {
    update.command = Twist2{};
    return update;
  }
  const LiftReport* report = nullptr;
  if (frame.lifts != nullptr) {
    const auto it = frame.lifts->find(ride_->lift_id());
    if (it != frame.lifts->end()) report = &it->second;
  }
  const LiftPhase before = ride_->phase();
  LiftStep step = ride_->Update(frame.now_s, *frame.pose, *frame.odom, frame.view.scan, report);
  if (InCar(before) != InCar(step.phase)) update.hold_localization = InCar(step.phase);
  update.lifts = std::move(step.requests);
  update.switch_floor = std::move(step.switch_floor);
  remaining_m_ = step.remaining_m;
  update.persist = step.phase != before || update.switch_floor.has_value();
  if (ride_->winding_up() && (step.phase == LiftPhase::kFailed || step.phase == LiftPhase::kDone)) {
    // Out of the car after a cancel (or the lift failed meanwhile): the mission ended already.
    ride_.reset();
    update.command = Twist2{};
    update.publish = true;
    return update;
  }
  if (step.phase == LiftPhase::kFailed) {
    ride_.reset();
    mission_->Fail(step.error);
    update.persist = update.over = true;
    return update;
  }
  if (step.phase == LiftPhase::kDone) {
    ride_.reset();
    NextGoal(update);
    return update;
  }
  update.command = step.twist;
  update.answers_frame = true;
  update.publish = true;
  return update;
}

MissionUpdate MissionRunner::OnPlan(const LegPlanQuery& query, const PlanResult& result,
                                    std::shared_ptr<const Costmap> costmap, std::uint64_t version, double now_s) {
  MissionUpdate update = PlanAnswered(query, result, std::move(costmap), version, now_s);
  return Settle(update);
}

MissionUpdate MissionRunner::PlanAnswered(const LegPlanQuery& query, const PlanResult& result,
                                          std::shared_ptr<const Costmap> costmap, std::uint64_t version, double now_s) {
  MissionUpdate update;
  if (query.reroute) {
    rerouting_ = false;
    // A failed reroute leaves the current path: it is still the best known way.
    if (!Current(query.ticket) || !policy_->has_path() || !result.ok()) return update;
    const LocalNavigatorOptions& o = options_.navigator;
    if (!query.blocked &&
        !PathsDiverge(result.plan.dense, Positions(policy_->path()), o.reroute_look_m, o.reroute_tolerance_m)) {
      return update;
    }
    policy_->SetPath(result.plan.waypoints, std::move(costmap));
    PathSet(result.plan.waypoints, update);
    path_version_ = version;
    remaining_m_ = result.plan.length_m;
    update.persist = true;
    return update;
  }
  if (!Current(query.ticket)) return update;  // overtaken
  planning_ = false;
  if (!result.ok()) {
    mission_->Fail(result.detail);
    update.persist = true;
    update.over = true;
    return update;
  }
  policy_->SetPath(result.plan.waypoints, std::move(costmap));
  PathSet(result.plan.waypoints, update);
  path_version_ = version;
  routed_s_ = now_s;
  leg_length_m_ = remaining_m_ = result.plan.length_m;
  update.persist = true;
  return update;
}

MissionUpdate MissionRunner::OnCheck(const PathCheckQuery& query, bool still_free,
                                     std::shared_ptr<const Costmap> costmap, std::uint64_t version) {
  checking_ = false;
  if (query.ticket != generation_) return {};
  if (still_free) {
    path_version_ = version;
    policy_->SetMap(std::move(costmap));  // the path stands; what is mapped and what the memory keeps clear of change
  } else {
    DropPath();
  }
  return {};
}

}  // namespace corridor::nav
