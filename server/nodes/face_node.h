// Feeds the face's expression machine from the bus (base motion, bumper, the control mode) and publishes the
// expression on face/expression, on the perception executor. A bump is seen however briefly the bumper was pressed
// (the control node stops pushing at once, so it may be pressed for a single odometry message between two ticks).
#pragma once

#include "face/expression.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class FaceNode final : public PeriodicNode {
 public:
  FaceNode(Executor& executor, Bus& bus, const face::ExpressionOptions& options = {});
  void Activate() override;

 private:
  void Tick() override;

  face::ExpressionMachine machine_;
  bool bumped_since_tick_ = false;  // on the node's executor
};

}  // namespace corridor::server
