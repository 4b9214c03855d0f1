// The robot's face: GET /api/v1/face (the expression, and what it said last) and POST /api/v1/face (an app's or
// building system's request: an expression for a while, a phrase to say, or both), the audio of what it said; and the
// detection hook: GET /api/v1/detections (what the robot sees now) and POST /api/v1/detections (an external
// detector's).
#pragma once

#include "drivers/clock.h"
#include "server/api/router.h"
#include "server/config/config.h"
#include "server/nodes/face_node.h"
#include "server/nodes/perception_node.h"
#include "server/runtime/bus.h"

namespace corridor::server {

class FaceApi {
 public:
  // `perception`: null when perception.enabled is false. `spoken`: the audio of what the face said lately.
  FaceApi(Bus& bus, const drivers::Clock& clock, const PerceptionOptions& options, PerceptionNode* perception,
          const SpokenPhrases& spoken);
  void AddRoutes(Router& routes) const;

 private:
  void AddDetectionRoutes(Router& routes) const;

  Bus& bus_;
  const drivers::Clock& clock_;
  const PerceptionOptions& options_;
  PerceptionNode* perception_;
  const SpokenPhrases& spoken_;
};

}  // namespace corridor::server
