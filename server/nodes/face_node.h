// Feeds the face's expression machine from the bus (base motion, bumper, the control mode) and publishes the
// expression on face/expression, on the perception executor.
#pragma once

#include <memory>

#include "face/expression.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"

namespace corridor::server {

class FaceNode final : public Node {
 public:
  FaceNode(Executor& executor, Bus& bus, const drivers::Clock& clock, const face::ExpressionOptions& options = {});
  void Activate() override;
  void Deactivate() override;

 private:
  void Tick();

  Executor& executor_;
  Bus& bus_;
  face::ExpressionMachine machine_;
  std::unique_ptr<PeriodicTimer> timer_;
};

}  // namespace corridor::server
