// Feeds the face's expression machine from the bus (base motion, bumper, the control mode) and publishes the
// expression on face/expression, on the perception executor.
#pragma once

#include "face/expression.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class FaceNode final : public PeriodicNode {
 public:
  FaceNode(Executor& executor, Bus& bus, const drivers::Clock& clock, const face::ExpressionOptions& options = {});

 private:
  void Tick() override;

  Bus& bus_;
  face::ExpressionMachine machine_;
};

}  // namespace corridor::server
