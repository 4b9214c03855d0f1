// Feeds the face's expression machine (face/expression.h) from the bus and publishes the expression, and what the
// robot says, on face/expression, on the perception executor, five times a second: base motion and the bumper (a bump
// is seen however briefly the bumper was pressed: the control node stops pushing at once, so it may be pressed for a
// single odometry message between two ticks), the control mode (teleop, a protective stop), localization's health,
// the mission (its phase, the place it goes to, whether it holds the robot still), the people detected
// (perception/detections, through face/social.h: near, in the way, looking at the robot; where the eyes look), and
// requests from apps (face/command: an expression for a while, a phrase to say).
#pragma once

#include "face/expression.h"
#include "face/social.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class FaceNode final : public PeriodicNode {
 public:
  FaceNode(Executor& executor, Bus& bus, const face::ExpressionOptions& options = {},
           const face::SocialOptions& social = {});
  void Activate() override;

 private:
  void Tick() override;
  void OnCommand(const FaceCommand& command);
  face::Situation Sample();
  void Say(std::string text, std::string kind);

  face::ExpressionMachine machine_;
  face::SocialSense social_;
  FaceState state_;
  bool bumped_since_tick_ = false;       // on the node's executor
  drivers::TimeNs still_since_ns_ = -1;  // the base has not moved since; -1: it is moving
};

}  // namespace corridor::server
