#include "server/nodes/mission_node.h"

#include <cmath>
#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"
#include "server/store/store.h"

namespace corridor::server {
namespace {

using nlohmann::json;

constexpr double kRateHz = 20.0;
// No depth frame for this long: the mission holds the robot still (the control loop also refuses forward motion).
constexpr double kNoFramesS = 0.2;
// Tracked objects older than this (three scans of a 10 Hz laser) are not used: a sensor that stops answering leaves
// the robot with MORP and the obstacle memory, as without tracking.
constexpr double kStaleTrackingS = 0.3;
// A bump older than this (from before the mission, say) is not where the robot is now.
constexpr double kFreshBumpS = 0.5;

json PoseJson(const nav::Pose2& p) { return {{"x", p.x_m}, {"y", p.y_m}, {"yaw", p.yaw_rad}}; }

}  // namespace

MissionNode::MissionNode(Executor& control, Bus& bus, PlannerService& planner,
                         const nav::LocalNavigatorOptions& navigator, std::function<void(json)> on_change)
    : PeriodicNode("mission", control, bus, kRateHz),
      planner_(planner),
      on_change_(std::move(on_change)),
      nominal_speed_mps_(navigator.follower.max_linear_mps),
      navigator_(navigator) {}

void MissionNode::Activate() {
  Subscribe(topics::kGroundLanes, "frame", [this](const auto& lanes) { Drive(*lanes); });
  PeriodicNode::Activate();
}

json MissionNode::DescribeLocked() const {
  const nav::Mission& m = *mission_;
  json goals = json::array();
  for (const nav::MissionGoal& g : m.goals()) {
    json goal = {{"x", g.pose.x_m}, {"y", g.pose.y_m}};
    if (g.has_yaw) goal["yaw"] = g.pose.yaw_rad;
    if (!g.place.empty()) goal["place"] = g.place;
    goals.push_back(goal);
  }
  json path = json::array();
  for (const nav::Waypoint& w : navigator_.path()) path.push_back(PoseJson(w.pose));
  const double speed = std::min(nominal_speed_mps_, m.speed_limit_mps());
  json doc = {{"id", m.id()},
              {"status", nav::ToString(m.status())},
              {"waypoints", goals},
              {"current_waypoint", m.current()},
              {"progress", m.Progress(remaining_m_, leg_length_m_)},
              {"eta_s", m.EtaSeconds(remaining_m_, speed)},
              {"remaining_on_leg_m", remaining_m_},
              {"path", path},
              {"policy", policy_mode_},
              {"error", m.error()}};
  doc["speed_limit_mps"] = std::isfinite(m.speed_limit_mps()) ? json(m.speed_limit_mps()) : json(nullptr);
  return doc;
}

void MissionNode::Changed() {
  const json doc = DescribeLocked();
  if (mission_->finished()) {
    // Tell the control node at once, rather than letting the last command go stale.
    bus().Get(topics::kMissionCommand).Publish(MissionCommand{clock().Now(), {}, false});
  }
  bus().Get(topics::kMission).Publish(MissionState{doc});
  if (on_change_) on_change_(doc);
}

json MissionNode::Start(std::vector<nav::MissionGoal> goals, double speed_limit_mps) {
  std::lock_guard lock(mutex_);
  if (mission_ && mission_->Cancel()) Changed();
  mission_ = std::make_unique<nav::Mission>(NewId(), std::move(goals), speed_limit_mps);
  navigator_.Clear();
  ++generation_;
  planning_ = false;
  checking_ = false;
  leg_length_m_ = remaining_m_ = 0.0;
  Changed();
  spdlog::info("mission {}: {} waypoint(s)", mission_->id(), mission_->goals().size());
  return DescribeLocked();
}

MissionNode::Outcome MissionNode::Transition(const std::string& id, bool (nav::Mission::*transition)(),
                                              bool drop_path) {
  std::lock_guard lock(mutex_);
  if (!mission_ || mission_->id() != id) return Outcome::kNotFound;
  if (!((*mission_).*transition)()) return Outcome::kConflict;
  if (drop_path) {
    navigator_.Clear();
    ++generation_;
    planning_ = false;
  }
  Changed();
  return Outcome::kOk;
}

// Pausing keeps the path; resuming plans the leg again from where the robot is (it may have been pushed or driven
// while paused); cancelling drops it.
MissionNode::Outcome MissionNode::Pause(const std::string& id) { return Transition(id, &nav::Mission::Pause, false); }
MissionNode::Outcome MissionNode::Resume(const std::string& id) { return Transition(id, &nav::Mission::Resume, true); }
MissionNode::Outcome MissionNode::Cancel(const std::string& id) { return Transition(id, &nav::Mission::Cancel, true); }

std::optional<json> MissionNode::Describe(const std::string& id) const {
  std::lock_guard lock(mutex_);
  if (!mission_ || mission_->id() != id) return std::nullopt;
  return DescribeLocked();
}

void MissionNode::PlanLeg(const nav::Pose2& from, std::function<void(const PlanReply&, bool current)> done) {
  const nav::MissionGoal& goal = mission_->current_goal();
  PlanRequest request;
  request.start = from.translation();
  request.goal = goal.pose.translation();
  if (goal.has_yaw) request.goal_yaw = goal.pose.yaw_rad;
  request.robot_at_start = true;
  // Round what blocked the robot lately, if anything did.
  request.blocking = navigator_.Blocking();
  request.blocking_radius_m = navigator_.options().blocked_radius_m;
  request.blocking_cost = static_cast<float>(navigator_.options().blocked_cost);
  const std::uint64_t generation = generation_;
  planner_.Plan(std::move(request), [this, generation, done = std::move(done)](PlanReply reply) {
    executor().Post([this, generation, done, reply = std::move(reply)] {
      std::lock_guard lock(mutex_);
      done(reply, generation == generation_ && mission_ && !mission_->finished());
    });
  });
}

void MissionNode::RequestPlan(const nav::Pose2& from) {
  planning_ = true;
  PlanLeg(from, [this](const PlanReply& reply, bool current) {
    if (!current) return;  // overtaken
    planning_ = false;
    if (!reply.result.ok()) {
      spdlog::warn("mission {}: {}", mission_->id(), reply.result.detail);
      mission_->Fail(reply.result.detail);
      Changed();
      return;
    }
    navigator_.SetPath(reply.result.plan.waypoints, reply.costmap);
    path_version_ = reply.version;
    routed_ns_ = clock().Now();
    leg_length_m_ = remaining_m_ = reply.result.plan.length_m;
    Changed();
  });
}

void MissionNode::Reroute(const nav::Pose2& from, bool blocked) {
  rerouting_ = true;
  routed_ns_ = clock().Now();
  PlanLeg(from, [this, blocked](const PlanReply& reply, bool current) {
    rerouting_ = false;
    // A failed reroute leaves the current path: it is still the best known way.
    if (!current || !navigator_.has_path() || !reply.result.ok()) return;
    std::vector<Eigen::Vector2d> path;
    for (const nav::Waypoint& w : navigator_.path()) path.push_back(w.pose.translation());
    const nav::LocalNavigatorOptions& o = navigator_.options();
    if (!blocked && !nav::PathsDiverge(reply.result.plan.dense, path, o.reroute_look_m, o.reroute_tolerance_m)) return;
    spdlog::info("mission {}: another way, {}", mission_->id(),
                 blocked ? "around what blocked the robot" : "around where people walk");
    navigator_.SetPath(reply.result.plan.waypoints, reply.costmap);
    path_version_ = reply.version;
    remaining_m_ = reply.result.plan.length_m;
    Changed();
  });
}

void MissionNode::CheckPath(const nav::Pose2& from) {
  checking_ = true;
  const std::uint64_t generation = generation_;
  std::vector<nav::Waypoint> path = navigator_.path();
  planner_.WithCostmap([this, generation, from, path = std::move(path)](std::shared_ptr<const nav::Costmap> costmap,
                                                                        std::uint64_t version) {
    // Is the rest of the path still free? The legs from the waypoint nearest the robot onward.
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < path.size(); ++i) {
      if ((path[i].pose.translation() - from.translation()).norm() <
          (path[nearest].pose.translation() - from.translation()).norm()) {
        nearest = i;
      }
    }
    bool free = true;
    for (std::size_t i = std::max<std::size_t>(nearest, 1); i < path.size() && free; ++i) {
      free = nav::SegmentTraversable(*costmap, path[i - 1].pose.translation(), path[i].pose.translation());
    }
    executor().Post([this, generation, free, version, costmap = std::move(costmap)] {
      std::lock_guard lock(mutex_);
      if (generation != generation_) return;
      checking_ = false;
      if (free) {
        path_version_ = version;
        navigator_.SetMap(costmap);  // the path stands; what is mapped and what the memory keeps clear of change
      } else {
        spdlog::info("mission {}: the map or zones changed across the path; replanning", mission_->id());
        navigator_.Clear();
        ++generation_;
      }
    });
  });
}

void MissionNode::Tick() {
  std::lock_guard lock(mutex_);
  if (!mission_ || mission_->finished()) return;
  const auto pose = bus().Get(topics::kPose).latest();
  const auto stop = [&] { bus().Get(topics::kMissionCommand).Publish(MissionCommand{clock().Now(), {}}); };
  if (!pose) return stop();
  if (mission_->status() == nav::MissionStatus::kPaused) return stop();
  if (!navigator_.has_path()) {
    if (!planning_) RequestPlan(pose->pose);
    return stop();
  }
  if (path_version_ != planner_.version() && !checking_) CheckPath(pose->pose);
  const double reroute_s = navigator_.options().reroute_s;
  if (reroute_s > 0.0 && !rerouting_ && mission_->status() == nav::MissionStatus::kActive && planner_.has_traffic() &&
      clock().Now() - routed_ns_ > drivers::FromSeconds(reroute_s)) {
    Reroute(pose->pose);
  }
  // Driving waits for depth frames; without them there is nothing safe to do but stand still.
  if (last_drive_ns_ < 0 || clock().Now() - last_drive_ns_ > drivers::FromSeconds(kNoFramesS)) {
    if (policy_mode_ != "waiting_for_depth") {
      policy_mode_ = "waiting_for_depth";
      bus().Get(topics::kMission).Publish(MissionState{DescribeLocked()});
    }
    stop();
  }
}

void MissionNode::Drive(const GroundLanes& lanes) {
  std::lock_guard lock(mutex_);
  const drivers::TimeNs now = clock().Now();
  const double dt_s = last_drive_ns_ < 0 ? 0.0 : drivers::ToSeconds(now - last_drive_ns_);
  last_drive_ns_ = now;
  if (!mission_ || mission_->finished() || mission_->status() == nav::MissionStatus::kPaused) return;
  if (!navigator_.has_path()) return;
  const auto pose = bus().Get(topics::kPose).latest();
  if (!pose) return;
  auto& command = bus().Get(topics::kMissionCommand);
  // The tracker's objects (from the laser, or the camera without one), while fresh: people to step out of the way of.
  const auto tracked = bus().Get(topics::kTrackedObjects).latest();
  const bool fresh = tracked && drivers::ToSeconds(now - tracked->received_ns) < kStaleTrackingS;
  // A bump since the last frame: remembered where it was, the way the control node says the base was driving.
  const auto bump = bus().Get(topics::kBumped).latest();
  if (bump && bump->stamp_ns > bump_seen_ns_ && now - bump->stamp_ns < drivers::FromSeconds(kFreshBumpS)) {
    bump_seen_ns_ = bump->stamp_ns;
    navigator_.Touched(pose->pose, bump->backing);
  }
  if (lanes.scan_view.range_m > 0.0) navigator_.See(pose->pose, lanes.scan, lanes.scan_view);
  const nav::LocalStep step = navigator_.Update(pose->pose, lanes.lanes, mission_->speed_limit_mps(), dt_s,
                                                fresh ? &tracked->surroundings : nullptr);
  remaining_m_ = step.remaining_m;
  policy_mode_ = step.evading ? "evade" : nav::ToString(step.mode);
  if (step.done) {
    mission_->GoalReached();
    navigator_.Clear();
    ++generation_;
    remaining_m_ = leg_length_m_ = 0.0;
    Changed();  // after the last goal this also tells the control node the mission is over
    if (!mission_->finished()) command.Publish(MissionCommand{now, {}});  // a brief stop before the next leg
    return;
  }
  if (step.replan) {
    spdlog::info("mission {}: the robot is more than {} m from its path; replanning", mission_->id(),
                 navigator_.options().replan_distance_m);
    navigator_.Clear();
    ++generation_;
    planning_ = false;
    command.Publish(MissionCommand{now, step.twist});  // still, unless stepping out of someone's way
    return;
  }
  if (step.blocked && !rerouting_) {
    spdlog::info("mission {}: no headway for {} s; planning around what the camera saw", mission_->id(),
                 navigator_.options().stuck_s);
    Reroute(pose->pose, true);
  }
  command.Publish(MissionCommand{now, step.twist, true, lanes.arrival_ns});
  bus().Get(topics::kMission).Publish(MissionState{DescribeLocked()});
}

}  // namespace corridor::server
