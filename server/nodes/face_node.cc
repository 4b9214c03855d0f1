#include "server/nodes/face_node.h"

#include <utility>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr double kRateHz = 5.0;
constexpr double kMovingMps = 0.02;
constexpr double kMovingRps = 0.05;

}  // namespace

FaceNode::FaceNode(Executor& executor, Bus& bus, const face::ExpressionOptions& options)
    : PeriodicNode("face", executor, bus, kRateHz), machine_(options) {}

void FaceNode::Activate() {
  Subscribe(topics::kOdometry, "odometry", [this](const auto& odometry) {
    if (odometry->bumper_pressed) bumped_since_tick_ = true;
  });
  PeriodicNode::Activate();
}

void FaceNode::Tick() {
  face::Situation s{.now_ns = clock().Now()};
  if (const auto odometry = bus().Get(topics::kOdometry).latest()) {
    s.moving = std::abs(odometry->velocity.linear_mps) > kMovingMps ||
               std::abs(odometry->velocity.angular_rps) > kMovingRps;
    const bool pressed_between_ticks = std::exchange(bumped_since_tick_, false);
    s.bumped = odometry->bumper_pressed || pressed_between_ticks;
  }
  if (const auto command = bus().Get(topics::kCmdVel).latest()) {
    s.driven = command->mode == nav::ControlMode::kTeleop;
    s.fault = command->mode == nav::ControlMode::kStopped;
  }
  if (const auto localization = bus().Get(topics::kLocalization).latest()) {
    s.lost = localization->estimate.health == nav::LocalizationHealth::kLost;
  }
  bus().Get(topics::kFaceExpression).Publish(FaceState{machine_.Update(s)});
}

}  // namespace corridor::server
