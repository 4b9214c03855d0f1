#include "server/nodes/mission_node.h"

#include <limits>
#include <utility>

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"
#include "server/store/store.h"

namespace corridor::server {
namespace {

constexpr double kMissionRateHz = 20.0;

std::optional<nav::Pose2> PoseOf(const std::shared_ptr<const StampedPose>& pose) {
  return pose ? std::optional<nav::Pose2>(pose->pose) : std::nullopt;
}

}  // namespace

const char* ToString(MissionStep step) {
  switch (step) {
    case MissionStep::kPause: return "pause";
    case MissionStep::kResume: return "resume";
    case MissionStep::kCancel: return "cancel";
  }
  return "?";
}

MissionNode::MissionNode(Executor& control, Bus& bus, PlannerService& planner, const nav::MissionRunnerOptions& options)
    : PeriodicNode("mission", control, bus, kMissionRateHz),
      planner_(planner),
      plan_loop_(Loop("plan")),
      docking_(options.docking),
      runner_(options) {}

void MissionNode::Activate() {
  Subscribe(topics::kGroundLanes, "frame", [this](const auto& ground) { Frame(*ground); });
  Subscribe(topics::kBattery, "battery", [this](const auto& battery) { Battery(*battery); });
  Subscribe(topics::kMapInUse, "map", [this](const auto& map) {
    runner_.SetDoors(map->doors);
    runner_.SetBuilding(map->building);
  });
  Subscribe(topics::kDoorStates, "doors", [this](const auto& states) { door_reports_ = states->doors; });
  Subscribe(topics::kLiftStates, "lifts", [this](const auto& states) { lift_reports_ = states->lifts; });
  Subscribe(topics::kLocalization, "localization", [this](const auto& localization) {
    const bool localized = localization->estimate.health != nav::LocalizationHealth::kLost;
    const nav::MissionUpdate update = runner_.SetLocalized(localized);
    if (update.persist || update.publish || update.over || update.command) {
      spdlog::warn("mission {}: {}", runner_.id(),
                   localized ? "localized again: resuming" : "localization lost: paused");
    }
    Carry(update);
    // Lost with the camera's narrow view, localization asks the robot to turn on the spot to see more.
    const double turn = runner_.MayLookAround() ? localization->look_around_rps : 0.0;
    auto& command = mission_command_topic_;
    if (turn > 0.0) {
      command.Publish(MissionCommand{clock().Now(), nav::Twist2{0.0, turn}, true});
      looking_around_ = true;
    } else if (std::exchange(looking_around_, false)) {
      // Stop turning; a mission that resumes drives again from its next frame.
      command.Publish(MissionCommand{clock().Now(), {}, runner_.has_mission() && !runner_.MayLookAround()});
    }
  });
  PeriodicNode::Activate();
}

void MissionNode::Carry(const nav::MissionUpdate& update, drivers::TimeNs frame_arrival_ns) {
  docked_ = runner_.docked();
  const drivers::TimeNs now = clock().Now();
  auto& command = mission_command_topic_;
  if (!update.doors.empty()) door_requests_topic_.Publish(DoorRequests{update.doors});
  if (!update.lifts.empty()) lift_requests_topic_.Publish(LiftRequests{update.lifts});
  if (update.hold_localization) {
    LocalizationCommand hold;
    hold.kind = *update.hold_localization ? LocalizationCommand::Kind::kHold : LocalizationCommand::Kind::kResume;
    localization_command_topic_.Publish(hold);
  }
  if (update.switch_floor) {
    const auto& [floor, pose] = *update.switch_floor;
    spdlog::info("mission {}: arrived on floor {} at ({:.2f}, {:.2f})", runner_.id(), floor, pose.x_m, pose.y_m);
    floor_topic_.Publish(FloorArrival{floor, pose});
  }
  if (update.over) {
    // Tell the control node at once, rather than letting the last command go stale.
    command.Publish(MissionCommand{now, {}, false});
  } else if (update.command) {
    command.Publish(
        MissionCommand{now, *update.command, true, update.answers_frame ? frame_arrival_ns : -1, update.docking});
  }
  if (update.persist || update.publish) {
    MissionState state = runner_.Snapshot();
    if (update.persist) changes_topic_.Publish(state);
    mission_topic_.Publish(std::move(state));
  }
  if (update.step && update.step->replan) {
    spdlog::info("mission {}: the robot has strayed from its path; replanning", runner_.id());
  }
  if (update.step) {
    local_step_topic_.Publish(LocalStepState{now, *update.step, runner_.policy().Remembered()});
  }
  if (update.plan) {
    const nav::LegPlanQuery query = *update.plan;
    if (query.blocked) spdlog::info("mission {}: no headway; planning around what the camera saw", runner_.id());
    PlanRequest request;
    request.start = query.start;
    request.goal = query.goal;
    request.goal_yaw = query.goal_yaw;
    request.robot_at_start = true;
    request.blocking = query.blocking;
    request.blocking_radius_m = query.blocking_radius_m;
    request.blocking_cost = query.blocking_cost;
    planner_.Plan(std::move(request), [this, query](PlanReply reply) {
      executor().Post([this, query, reply = std::move(reply)] {
        Run(plan_loop_, [&] {
          if (!reply.result.ok() && !query.reroute) {
            spdlog::warn("mission {}: {}", runner_.id(), reply.result.detail);
          }
          Carry(runner_.OnPlan(query, reply.result, reply.costmap, reply.version, now_s()));
        });
      });
    });
  }
  if (update.check) {
    planner_.WithCostmap(
        [this, query = *update.check](std::shared_ptr<const nav::Costmap> costmap, std::uint64_t version) {
          const bool free = nav::RestOfPathTraversable(*costmap, query.path, query.from);
          executor().Post([this, query, free, version, costmap = std::move(costmap)] {
            Run(plan_loop_, [&] {
              if (!free) spdlog::info("mission {}: the map or zones changed across the path; replanning", runner_.id());
              Carry(runner_.OnCheck(query, free, costmap, version));
            });
          });
        });
  }
}

void MissionNode::Start(std::vector<nav::MissionGoal> goals, double speed_limit_mps,
                        std::function<void(MissionState)> done) {
  executor().Post([this, goals = std::move(goals), speed_limit_mps, done = std::move(done)]() mutable {
    Run("start", [&] {
      if (runner_.docked() && !goals.empty() && goals.front().action != nav::GoalAction::kUndock) {
        // Off the dock first, straight back to its staging pose.
        goals.insert(goals.begin(), nav::UndockGoal(PoseOf(pose_topic_.latest()), docking_.dock));
      }
      std::optional<nav::MissionSnapshot> cancelled;
      const nav::MissionUpdate update =
          runner_.Start(nav::Mission(NewId(), std::move(goals), speed_limit_mps), &cancelled);
      if (cancelled) changes_topic_.Publish(*cancelled);
      Carry(update);
      MissionState started = runner_.Snapshot();
      spdlog::info("mission {}: {} waypoint(s)", started.id, started.goals.size());
      done(std::move(started));
    });
  });
}

void MissionNode::Extend(const std::string& id, std::vector<nav::MissionGoal> goals,
                         std::function<void(Outcome)> done) {
  executor().Post([this, id, goals = std::move(goals), done = std::move(done)]() mutable {
    Run("extend", [&] {
      nav::MissionUpdate update;
      const nav::TransitionOutcome outcome = runner_.Extend(id, std::move(goals), &update);
      Carry(update);
      done(OutcomeOf(id, outcome));
    });
  });
}

void MissionNode::Step(MissionStep step, const std::string& id, std::function<void(Outcome)> done) {
  executor().Post([this, step, id, done = std::move(done)] {
    Run(ToString(step), [&] {
      nav::MissionUpdate update;
      nav::TransitionOutcome outcome = nav::TransitionOutcome::kNotFound;
      switch (step) {
        case MissionStep::kPause: outcome = runner_.Pause(id, &update); break;
        case MissionStep::kResume: outcome = runner_.Resume(id, &update); break;
        case MissionStep::kCancel: outcome = runner_.Cancel(id, &update); break;
      }
      Carry(update);
      if (done) done(OutcomeOf(id, outcome));
    });
  });
}

MissionNode::Outcome MissionNode::OutcomeOf(const std::string& id, nav::TransitionOutcome outcome) const {
  if (!runner_.has_mission() || runner_.id() != id) return {outcome, std::nullopt};
  return {outcome, runner_.Snapshot()};
}

void MissionNode::Battery(const drivers::BatteryState& battery) {
  runner_.SetOnCharger(battery.on_charger);
  docked_ = runner_.docked();
}

void MissionNode::Tick() {
  Carry(runner_.Tick(now_s(), PoseOf(pose_topic_.latest()), planner_.version(), planner_.has_traffic()));
}

void MissionNode::Frame(const GroundLanes& ground) {
  nav::FrameInput in;
  in.now_s = now_s();
  in.pose = PoseOf(pose_topic_.latest());
  if (const auto odometry = odometry_topic_.latest()) in.odom = odometry->odom_T_base;
  in.view.lanes = &ground.lanes;
  in.view.scan = &ground.scan;
  in.view.scan_view = ground.scan_view;
  in.view.obstacles = &ground.obstacles;
  const auto tracked = tracked_objects_topic_.latest();
  if (tracked) {
    in.tracked = &tracked->surroundings;
    in.tracked_received_s = drivers::ToSeconds(tracked->received_ns);
  }
  if (const auto bump = bumped_topic_.latest()) {
    in.bump_s = drivers::ToSeconds(bump->stamp_ns);
    in.bump_backing = bump->backing;
  }
  in.doors = &door_reports_;
  in.lifts = &lift_reports_;
  Carry(runner_.Frame(in), ground.arrival_ns);
}

}  // namespace corridor::server
