#include "server/nodes/sim_node.h"

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// At most this much simulated time per tick; beyond it the simulator runs slower than real time instead of
// stalling the executor in an ever-growing catch-up.
constexpr drivers::TimeNs kMaxCatchUpNs = drivers::kNsPerSecond / 10;

}  // namespace

SimNode::SimNode(Executor& executor, Bus& bus, drivers::sim::SimRobot& robot, std::filesystem::path pose_file,
                 std::string world, std::shared_ptr<const drivers::sim::Floors> floors)
    : Node("sim", executor, bus),
      robot_(robot),
      loop_(Loop("step")),
      pose_file_(std::move(pose_file)),
      world_(std::move(world)),
      floors_(std::move(floors)) {}

void SimNode::Activate() {
  wall_start_ns_ = clock().Now();
  sim_start_ns_ = robot_.now_ns();
  has_pedestrians_ = !robot_.pedestrians().empty();
  PublishTruth();  // the people once even when there are none: the topic then says so
  if (executor().schedule() == Schedule::kThreads) {
    timer_ =
        std::make_unique<PeriodicTimer>(executor(), std::chrono::nanoseconds(drivers::FromSeconds(robot_.step_s())),
                                        [this] { Run(loop_, [this] { KeepUp(); }); });
  }
  SetHealth(Health::kOk, "");
}

void SimNode::Deactivate() {
  if (timer_) timer_->Stop();
  SetHealth(Health::kInactive, "");
}

void SimNode::Cleanup() {
  if (pose_file_.empty()) return;
  try {
    SavePose(pose_file_, {world_, robot_.true_pose(), 0.0, 0.0});
  } catch (const std::exception& e) {
    spdlog::error("sim: the robot's pose at the stop was not saved: {}", e.what());
  }
}

void SimNode::Step() {
  Run(loop_, [this] {
    robot_.Step();
    PublishTruth();
  });
}

void SimNode::KeepUp() {
  const drivers::TimeNs target = sim_start_ns_ + (clock().Now() - wall_start_ns_);
  const drivers::TimeNs limit = robot_.now_ns() + kMaxCatchUpNs;
  while (robot_.now_ns() < target && robot_.now_ns() < limit) robot_.Step();
  if (robot_.now_ns() < target) {
    // Behind by more than a catch-up: let real time go and report that simulated time is slower.
    sim_start_ns_ -= target - robot_.now_ns();
    SetHealth(Health::kDegraded, "slower than real time");
  }
  PublishTruth();
}

void SimNode::PublishTruth() {
  const nav::Pose2 truth = robot_.true_pose();
  nav::Pose2 on_floor = truth;
  if (floors_) {
    const Eigen::Vector2d shift = floors_->offsets[static_cast<std::size_t>(floors_->FloorAt(truth.translation()))];
    on_floor.x_m -= shift.x();
    on_floor.y_m -= shift.y();
  }
  bus().Get(topics::kSimTruePose).Publish(StampedPose{robot_.now_ns(), on_floor});
  if (!pose_file_.empty()) {
    const SavedPose now{world_, truth, 0.0, 0.0};
    if (!saved_ || MovedEnough(*saved_, now)) {
      SavePose(pose_file_, now);
      saved_ = now;
    }
  }
  if (!has_pedestrians_ && bus().Get(topics::kSimPedestrians).latest()) return;
  SimPedestrians out{robot_.pedestrian_radius_m(), {}};
  for (const drivers::sim::Pedestrian& p : robot_.pedestrians()) out.people.push_back({p.position, p.velocity});
  bus().Get(topics::kSimPedestrians).Publish(std::move(out));
}

}  // namespace corridor::server
