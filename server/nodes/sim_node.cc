#include "server/nodes/sim_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// At most this much simulated time per tick; beyond it the simulator runs slower than real time instead of
// stalling the executor in an ever-growing catch-up.
constexpr drivers::TimeNs kMaxCatchUpNs = drivers::kNsPerSecond / 10;

}  // namespace

SimNode::SimNode(Executor& executor, Bus& bus, drivers::sim::SimRobot& robot, const drivers::Clock& wall_clock)
    : PeriodicNode("sim", executor, wall_clock, 1.0 / robot.step_s()), bus_(bus), robot_(robot) {}

void SimNode::Activate() {
  wall_start_ns_ = clock().Now();
  sim_start_ns_ = robot_.now_ns();
  bus_.Get(topics::kSimTruePose).Publish(StampedPose{robot_.now_ns(), robot_.true_pose()});
  has_pedestrians_ = !robot_.pedestrians().empty();
  PublishPedestrians();  // once even when there are none: the topic then says so
  PeriodicNode::Activate();
}

void SimNode::Tick() {
  const drivers::TimeNs target = sim_start_ns_ + (clock().Now() - wall_start_ns_);
  const drivers::TimeNs limit = robot_.now_ns() + kMaxCatchUpNs;
  while (robot_.now_ns() < target && robot_.now_ns() < limit) robot_.Step();
  if (robot_.now_ns() < target) {
    // Behind by more than a catch-up: let real time go and report that simulated time is slower.
    sim_start_ns_ -= target - robot_.now_ns();
    SetHealth(Health::kDegraded, "slower than real time");
  }
  bus_.Get(topics::kSimTruePose).Publish(StampedPose{robot_.now_ns(), robot_.true_pose()});
  if (has_pedestrians_) PublishPedestrians();
}

void SimNode::PublishPedestrians() {
  SimPedestrians out{robot_.pedestrian_radius_m(), {}};
  for (const drivers::sim::Pedestrian& p : robot_.pedestrians()) out.people.push_back({p.position, p.velocity});
  bus_.Get(topics::kSimPedestrians).Publish(std::move(out));
}

}  // namespace corridor::server
